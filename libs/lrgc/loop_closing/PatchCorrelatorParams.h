/* TPatchCorrelatorParams: section [PatchCorrelator] of the global correlation stage
 * (Gutmann & Konolige, section 2.3): the grid of the correlation operator and the three
 * post-match filters (score, ambiguity, variance). Memory holds metres and radians; keys in
 * degrees end in _deg. Defaults: chosen on the benchmark logs (doc/global-correlation.md, and
 * the test PatchCorrelatorRealLog: 333 of 346 true loops accepted, 0 of 346 displaced windows).
 */
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <string>

namespace lrgc
{
struct TPatchCorrelatorParams : public mrpt::config::CLoadableOptions
{
	/** Cell size of the old-map grid [m]; also the translation step of the pose grid. */
	double resolution_m = 0.05;
	/** Standard deviation of the Gaussian folded into the old map [m] (scan noise of map
	 * and patch plus the half-cell discretisation). */
	double blur_sigma_m = 0.10;
	/** Rotation step of the pose grid [rad]; 0 derives it from the patch so that its
	 * farthest point moves by one cell per step: resolution_m / max |p_patch|. */
	double angular_step = 0;

	/** Filter 1, high score: least mean map probability over patch cells, in [0,1]. The
	 * search also uses it as its pruning floor: no pose scoring less is ever returned. */
	double min_score = 0.60;
	/** Filter 2, low ambiguity: least ratio of the best cluster's peak score to the best
	 * score outside that cluster (>= 1). */
	double min_ambiguity = 1.20;
	/** Filter 3, low variance: largest standard deviation of the best cluster in x and in
	 * y [m], and in heading [rad] (the paper: "less than 20 cm in any direction"). */
	double max_std_xy_m = 0.20;
	double max_std_phi = 2.0 * 3.14159265358979323846 / 180;

	/** Poses within cluster_radius_m [m] and cluster_radius_phi [rad] of the best pose belong
	 * to its cluster; the best pose outside them is the rival of the ambiguity filter. */
	double cluster_radius_m = 0.5;
	double cluster_radius_phi = 10.0 * 3.14159265358979323846 / 180;
	/** Sharpness of the normalised response used for the cluster's covariance: a pose
	 * scoring s has weight exp(-(s_best - s) / (cluster_score_scale * s_best)). */
	double cluster_score_scale = 0.05;

	void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
							const std::string& section) override;
	void saveToConfigFile(mrpt::config::CConfigFileBase& target,
						  const std::string& section) const override;
	/** Throws, naming the key, if a value is out of range. */
	void validate(const std::string& section = "PatchCorrelator") const;
};

}  // namespace lrgc
