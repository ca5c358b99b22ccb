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
	resolution_m = readDouble(c, s, "resolution_m", resolution_m);
	blur_sigma_m = readDouble(c, s, "blur_sigma_m", blur_sigma_m);
	angular_step = readDegrees(c, s, "angular_step_deg", angular_step);
	min_score = readDouble(c, s, "min_score", min_score);
	min_ambiguity = readDouble(c, s, "min_ambiguity", min_ambiguity);
	max_std_xy_m = readDouble(c, s, "max_std_xy_m", max_std_xy_m);
	max_std_phi = readDegrees(c, s, "max_std_phi_deg", max_std_phi);
	cluster_radius_m = readDouble(c, s, "cluster_radius_m", cluster_radius_m);
	cluster_radius_phi = readDegrees(c, s, "cluster_radius_phi_deg", cluster_radius_phi);
	cluster_score_scale = readDouble(c, s, "cluster_score_scale", cluster_score_scale);
	validate(s);
}

void TPatchCorrelatorParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
											  const std::string& s) const
{
	writeValue(c, s, "resolution_m", resolution_m,
			   "Old-map cell and translation step of the pose grid [m]");
	writeValue(c, s, "blur_sigma_m", blur_sigma_m,
			   "Gaussian sigma folded into the old map (scan noise + discretisation) [m]");
	writeDegrees(
		c, s, "angular_step_deg", angular_step,
		"Heading step of the pose grid [deg]; 0 = resolution_m / farthest patch point");
	writeValue(c, s, "min_score", min_score,
			   "Filter 1: least mean map probability over patch cells [0..1]");
	writeValue(c, s, "min_ambiguity", min_ambiguity,
			   "Filter 2: least ratio best-cluster peak / best score outside it [>= 1]");
	writeValue(c, s, "max_std_xy_m", max_std_xy_m,
			   "Filter 3: largest std dev of the best cluster in x and in y [m]");
	writeDegrees(c, s, "max_std_phi_deg", max_std_phi,
				 "Filter 3: largest std dev of the best cluster in heading [deg]");
	writeValue(c, s, "cluster_radius_m", cluster_radius_m,
			   "Poses this close to the best one [m] belong to its cluster");
	writeDegrees(c, s, "cluster_radius_phi_deg", cluster_radius_phi,
				 "... and this close in heading [deg]");
	writeValue(c, s, "cluster_score_scale", cluster_score_scale,
			   "Relative score drop giving weight 1/e in the cluster covariance [0..1]");
}

void TPatchCorrelatorParams::validate(const std::string& s) const
{
	// Below 1 cm (finer than a 2D laser's range noise, which blur_sigma_m models) the grids
	// outgrow memory: 0.001 m made every loop search's old map a 12714 x 22108-cell grid on
	// SENA (2.3 GB), the run then failing at its end (issue 30).
	requireParam(resolution_m >= 0.01 && resolution_m <= 1, s, "resolution_m",
				 "must be in [0.01, 1] m");
	requireParam(blur_sigma_m >= 0 && blur_sigma_m <= 2, s, "blur_sigma_m",
				 "must be in [0, 2] m");
	requireParam(angular_step >= 0 && angular_step <= DEG2RAD(10.0), s, "angular_step_deg",
				 "must be in [0, 10] deg");
	requireParam(min_score >= 0 && min_score <= 1, s, "min_score", "must be in [0, 1]");
	requireParam(min_ambiguity >= 1 && std::isfinite(min_ambiguity), s, "min_ambiguity",
				 "must be >= 1 (a ratio of scores)");
	requireParam(max_std_xy_m > 0, s, "max_std_xy_m", "must be > 0 m");
	requireParam(max_std_phi > 0, s, "max_std_phi_deg", "must be > 0 deg");
	requireParam(cluster_radius_m >= 0, s, "cluster_radius_m", "must be >= 0 m");
	requireParam(cluster_radius_phi >= 0, s, "cluster_radius_phi_deg", "must be >= 0 deg");
	requireParam(cluster_score_scale > 0 && cluster_score_scale <= 1, s, "cluster_score_scale",
				 "must be in (0, 1]");
}

}  // namespace lrgc
