/* Section [LocalRegistration]: the parameters of CLocalRegistration, apart from the class so
 * that the map builder's public header (MapBuilderParams.h) needs none of the stage's
 * internals. */
#pragma once

#include <lrgc/pose_graph/LinkNoise.h>
#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/core/bits_math.h>

#include <cmath>
#include <cstddef>
#include <string>

namespace lrgc
{
struct TLocalRegistrationParams : public mrpt::config::CLoadableOptions
{
	/** K: keyframes in the window (paper: K >= 7 at 0.3 m) while the scans' prior comes from
	 * odometry. 15 put local registration alone below published scan matching on Intel,
	 * ACES and MIT-CSAIL (doc/generalisation.md); 10 did not on MIT-CSAIL. */
	size_t window_size = 15;
	/** K while the prior is the constant-velocity model (no odometry): a longer window of
	 * laser-only keyframes carries their heading drift into the patch (Intel laser-only
	 * 0.511 m at 10, 1.23 m at 15). */
	size_t laser_only_window_size = 10;
	size_t max_pairwise_links =
		5;  //!< pairwise scan-match links per new keyframe (spread over the window)
	double min_link_inlier_fraction =
		0.5;                          //!< pairwise link only if this fraction of points matched
	double glitch_gate_chi2 = 16.27;  //!< [chi2, 3 dof] prior/match disagreement (p = 0.001)
	double wide_search_angle = mrpt::DEG2RAD(90.0);  //!< [rad] (key wide_search_angle_deg)
	double glitch_min_turn = mrpt::DEG2RAD(
		30.0);  //!< [rad] a step turning more is suspect (key glitch_min_turn_deg)
	double glitch_min_gap_s = 1.0;  //!< [s] a step after a longer pause in the scans is suspect
	/** Free-space tolerance of local matches, replacing [ScanMatcher]'s: with an odometry
	 * prior a wrong match is unlikely, while people walking through the window's scans and
	 * glass make the strict loop-closing value reject good local matches on real logs. */
	double max_free_space_violation = 0.3;
	/** [m] A crowd in the window's free space: where the prior's heading std exceeds
	 * crowd_min_prior_std, the plain match's free-space check counts only runs of violating
	 * points at least this long (people are narrower, a misplaced wall is longer); 0: off.
	 * Sparse steps among visitors (a museum, 1.5 m a scan, a 20 m laser, 25 people): their
	 * right matches were refused, the prior stood and the map bent (doc/generalisation.md,
	 * the museum). Where the prior is tight (dense steps) refusing a match costs little, and
	 * the crowded hall keeps the strict count there. */
	double crowd_min_run_m = 0.8;
	/** [rad] (key crowd_min_prior_std_deg) The prior's heading std above which
	 * crowd_min_run_m applies: about 1.2 deg a dense step in the crowded hall, 4-5 deg a
	 * sparse one in the museum. */
	double crowd_min_prior_std = mrpt::DEG2RAD(2.0);
	TLinkNoise link_noise;  //!< pairwise links; keys link_floor_xy_m [m], link_floor_phi_deg
	/** Noise floor of the patch link; keys patch_link_floor_xy_m [m], patch_link_floor_phi_deg.
	 * Tighter than the pairwise links': the patch of K scans has dense, well-fitted lines.
	 * Measured, local registration alone: see doc/architecture.md. */
	TLinkNoise patch_link_noise{0.005, 0.1 * M_PI / 180};
	/** Link each new keyframe to the previous one by its registration against the window
	 * patch (scan to map), besides the pairwise links (scan to scan). Used where the scan's
	 * prior came from odometry (laser-only runs keep the pairwise links alone). */
	bool patch_link = true;
	/** Scale of the pairwise links' information (after the split among them). Scan-to-scan
	 * matches against one sparse scan err more than their covariance says: at full weight
	 * they doubled the heading drift of local registration on Intel (1.5 vs 0.7 deg per
	 * 1000 scans, median, at 0.05); at 0.05 they mainly hold the window where the patch match
	 * fails (doc/architecture.md). */
	double pairwise_link_weight = 0.05;
	/** A scan whose odometry step is zero (wheels that did not turn: under 1 mm and 1 mrad)
	 * is not matched again while the window and its poses are unchanged: it takes the last
	 * accepted match's pose relative to the window, composed with that step, and its
	 * covariance. Such a match would only re-measure the same pose (the wheels already
	 * overrule one that moves the robot); ACES stands still for 35 % of its scans. Off by
	 * default (stop 62, doc/parameters.md): ACES 0.94x CPU but the same wall time (5 paired
	 * runs), issue 29's ACES pieces test 0.00009 m worse over six starts, and on Killian one
	 * scan (11370) at 32-51 ms over five runs where main's worst is 36-41 ms. */
	bool reuse_match_when_still = false;
	/** [m] ... and only while the scan's ranges agree with the matched scan's: the median
	 * change of the nearest return per 1 deg bearing bin (CRangeImage::medianChange) at most
	 * this. Wheels that stand still while the robot moves (lagging odometry: 19 of ACES's
	 * 2608 zero steps, 2-5 cm) fail it; a still laser's own noise (ACES's 1 cm steps: 0 or 1
	 * cm) passes. A noisier laser fails it and is matched again, as without the reuse. */
	double still_max_range_change_m = 0.015;

	void loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
							const std::string& s) override;
	void saveToConfigFile(mrpt::config::CConfigFileBase& c,
						  const std::string& s) const override;
};

}  // namespace lrgc
