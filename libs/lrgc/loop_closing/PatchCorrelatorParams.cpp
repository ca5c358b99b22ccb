#include <lrgc/loop_closing/PatchCorrelatorParams.h>

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/bits_math.h>

#include <lrgc/common/params_io.h>

#include <cmath>

namespace lrgc
{
using mrpt::DEG2RAD;
using mrpt::RAD2DEG;

void TPatchCorrelatorParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
												const std::string& s)
{
	rejectUnknownKeys(*this, c, s);
	resolution = readDouble(c, s, "resolution", resolution);
	blurSigma = readDouble(c, s, "blur_sigma", blurSigma);
	angularStep = readDegrees(c, s, "angular_step_deg", angularStep);
	minScore = readDouble(c, s, "min_score", minScore);
	minAmbiguity = readDouble(c, s, "min_ambiguity", minAmbiguity);
	maxStdXY = readDouble(c, s, "max_std_xy", maxStdXY);
	maxStdTheta = readDegrees(c, s, "max_std_theta_deg", maxStdTheta);
	clusterRadiusXY = readDouble(c, s, "cluster_radius", clusterRadiusXY);
	clusterRadiusTheta = readDegrees(c, s, "cluster_radius_deg", clusterRadiusTheta);
	clusterScoreScale = readDouble(c, s, "cluster_score_scale", clusterScoreScale);
	validate(s);
}

void TPatchCorrelatorParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
											  const std::string& s) const
{
	const int w = -1, wc = -1;  // no padding: the key set must match what is read
	c.write(s, "resolution", resolution, w, wc,
			"Old-map cell and translation step of the pose grid [m]");
	c.write(s, "blur_sigma", blurSigma, w, wc,
			"Gaussian sigma folded into the old map (scan noise + discretisation) [m]");
	c.write(s, "angular_step_deg", RAD2DEG(angularStep), w, wc,
			"Heading step of the pose grid [deg]; 0 = resolution / farthest patch point");
	c.write(s, "min_score", minScore, w, wc,
			"Filter 1: least mean map probability over patch cells [0..1]");
	c.write(s, "min_ambiguity", minAmbiguity, w, wc,
			"Filter 2: least ratio best-cluster peak / best score outside it [>= 1]");
	c.write(s, "max_std_xy", maxStdXY, w, wc,
			"Filter 3: largest std dev of the best cluster in x and in y [m]");
	c.write(s, "max_std_theta_deg", RAD2DEG(maxStdTheta), w, wc,
			"Filter 3: largest std dev of the best cluster in heading [deg]");
	c.write(s, "cluster_radius", clusterRadiusXY, w, wc,
			"Poses this close to the best one [m] belong to its cluster");
	c.write(s, "cluster_radius_deg", RAD2DEG(clusterRadiusTheta), w, wc,
			"... and this close in heading [deg]");
	c.write(s, "cluster_score_scale", clusterScoreScale, w, wc,
			"Relative score drop giving weight 1/e in the cluster covariance [0..1]");
}

void TPatchCorrelatorParams::validate(const std::string& s) const
{
	requireParam(resolution > 0 && resolution <= 1, s, "resolution", "must be in (0, 1] m");
	requireParam(blurSigma >= 0 && blurSigma <= 2, s, "blur_sigma", "must be in [0, 2] m");
	requireParam(angularStep >= 0 && angularStep <= DEG2RAD(10.0), s, "angular_step_deg",
				 "must be in [0, 10] deg");
	requireParam(minScore >= 0 && minScore <= 1, s, "min_score", "must be in [0, 1]");
	requireParam(minAmbiguity >= 1 && std::isfinite(minAmbiguity), s, "min_ambiguity",
				 "must be >= 1 (a ratio of scores)");
	requireParam(maxStdXY > 0, s, "max_std_xy", "must be > 0 m");
	requireParam(maxStdTheta > 0, s, "max_std_theta_deg", "must be > 0 deg");
	requireParam(clusterRadiusXY >= 0, s, "cluster_radius", "must be >= 0 m");
	requireParam(clusterRadiusTheta >= 0, s, "cluster_radius_deg", "must be >= 0 deg");
	requireParam(clusterScoreScale > 0 && clusterScoreScale <= 1, s, "cluster_score_scale",
				 "must be in (0, 1]");
}

}  // namespace lrgc
