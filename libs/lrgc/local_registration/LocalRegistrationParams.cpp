#include <lrgc/local_registration/LocalRegistrationParams.h>
#include <lrgc/common/params_io.h>
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/format.h>

#include <algorithm>

namespace lrgc
{
void TLocalRegistrationParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
												  const std::string& s)
{
	rejectUnknownKeys(TLocalRegistrationParams(), c, s);
	window_size = readCount(c, s, "window_size", window_size);
	laser_only_window_size = readCount(c, s, "laser_only_window_size", laser_only_window_size);
	max_pairwise_links = readCount(c, s, "max_pairwise_links", max_pairwise_links);
	min_link_inlier_fraction =
		readDouble(c, s, "min_link_inlier_fraction", min_link_inlier_fraction);
	glitch_gate_chi2 = readDouble(c, s, "glitch_gate_chi2", glitch_gate_chi2);
	wide_search_angle = readDegrees(c, s, "wide_search_angle_deg", wide_search_angle);
	glitch_min_turn = readDegrees(c, s, "glitch_min_turn_deg", glitch_min_turn);
	glitch_min_gap_s = readDouble(c, s, "glitch_min_gap_s", glitch_min_gap_s);
	requireParam(glitch_min_gap_s > 0, s, "glitch_min_gap_s", "must be > 0");
	max_free_space_violation =
		readDouble(c, s, "max_free_space_violation", max_free_space_violation);
	requireParam(max_free_space_violation >= 0 && max_free_space_violation <= 1, s,
				 "max_free_space_violation", "must be in [0, 1]");
	crowd_min_run_m = readDouble(c, s, "crowd_min_run_m", crowd_min_run_m);
	requireParam(crowd_min_run_m >= 0, s, "crowd_min_run_m", "must be >= 0");
	crowd_min_prior_std = readDegrees(c, s, "crowd_min_prior_std_deg", crowd_min_prior_std);
	requireParam(crowd_min_prior_std >= 0, s, "crowd_min_prior_std_deg", "must be >= 0");
	requireParam(glitch_min_turn >= 0, s, "glitch_min_turn_deg", "must be >= 0");
	link_noise.load(c, s, "");
	requireParam(window_size >= 2 && window_size <= 100, s, "window_size",
				 "must be in [2, 100]");
	requireParam(laser_only_window_size >= 2 && laser_only_window_size <= 100, s,
				 "laser_only_window_size", "must be in [2, 100]");
	requireParam(
		max_pairwise_links >= 1 &&
			max_pairwise_links < std::min(window_size, laser_only_window_size),
		s, "max_pairwise_links",
		mrpt::format("%zu must be below window_size (%zu) and laser_only_window_size (%zu)",
					 max_pairwise_links, window_size, laser_only_window_size));
	requireParam(min_link_inlier_fraction > 0 && min_link_inlier_fraction <= 1, s,
				 "min_link_inlier_fraction", "must be in (0, 1]");
	requireParam(glitch_gate_chi2 > 0, s, "glitch_gate_chi2", "must be > 0");
	patch_link = readBool(c, s, "patch_link", patch_link);
	patch_link_noise.load(c, s, "patch_");
	pairwise_link_weight = readDouble(c, s, "pairwise_link_weight", pairwise_link_weight);
	requireParam(pairwise_link_weight > 0 && pairwise_link_weight <= 1, s,
				 "pairwise_link_weight", "must be in (0, 1]");
	reuse_match_when_still = readBool(c, s, "reuse_match_when_still", reuse_match_when_still);
	still_max_range_change_m =
		readDouble(c, s, "still_max_range_change_m", still_max_range_change_m);
	requireParam(still_max_range_change_m >= 0, s, "still_max_range_change_m", "must be >= 0");
	requireParam(wide_search_angle >= 0 && wide_search_angle <= M_PI, s,
				 "wide_search_angle_deg", "must be in [0, 180]");
}

void TLocalRegistrationParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
												const std::string& s) const
{
	writeValue(
		c, s, "window_size", uint64_t(window_size),
		"K: keyframes registered together while the prior comes from odometry (paper: K >= 7)");
	writeValue(c, s, "laser_only_window_size", uint64_t(laser_only_window_size),
			   "K while the prior is the constant-velocity model (no odometry)");
	writeValue(c, s, "max_pairwise_links", uint64_t(max_pairwise_links),
			   "Pairwise scan-match links per new keyframe, spread over the window");
	writeValue(c, s, "min_link_inlier_fraction", min_link_inlier_fraction,
			   "Min fraction of matched points for a pairwise scan-match link");
	writeValue(c, s, "glitch_gate_chi2", glitch_gate_chi2,
			   "[chi2, 3 dof] Odometry/match disagreement that triggers the wide search");
	link_noise.save(c, s, "",
					"every pairwise scan-match link (real-scan errors the matcher cannot see)");
	writeDegrees(c, s, "wide_search_angle_deg", wide_search_angle,
				 "[deg] Half-width of the rotational search after an odometry glitch");
	writeDegrees(c, s, "glitch_min_turn_deg", glitch_min_turn,
				 "[deg] A predicted step turning more than this is suspect: wide search if the "
				 "match fails");
	writeValue(c, s, "glitch_min_gap_s", glitch_min_gap_s,
			   "[s] A step after a longer pause in the scans is suspect too");
	writeValue(c, s, "max_free_space_violation", max_free_space_violation,
			   "Local matches: tolerated fraction of points where the window saw free space "
			   "(replaces [ScanMatcher] max_free_space_violation here)");
	writeValue(c, s, "crowd_min_run_m", crowd_min_run_m,
			   "[m] Where the prior's heading std exceeds crowd_min_prior_std_deg, the plain "
			   "match's free-space check counts only runs of violating points this long "
			   "(people are narrower); 0: off");
	writeDegrees(c, s, "crowd_min_prior_std_deg", crowd_min_prior_std,
				 "[deg] The prior's heading std above which crowd_min_run_m applies");
	writeValue(c, s, "patch_link", patch_link,
			   "Link each keyframe to the previous one by its match against the window patch "
			   "(scan to map)");
	patch_link_noise.save(c, s, "patch_", "the patch link");
	writeValue(c, s, "pairwise_link_weight", pairwise_link_weight,
			   "Pairwise (scan to scan) links' information is scaled by this, after the split "
			   "among them");
	writeValue(c, s, "reuse_match_when_still", reuse_match_when_still,
			   "A scan with a zero odometry step takes the last match's pose relative to the "
			   "unchanged window instead of being matched again");
	writeValue(c, s, "still_max_range_change_m", still_max_range_change_m,
			   "[m] ... while the median change of its ranges (per 1 deg bin) against the "
			   "matched scan's is at most this");
}

}  // namespace lrgc
