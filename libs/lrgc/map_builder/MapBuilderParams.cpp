#include <lrgc/map_builder/MapBuilderParams.h>

#include <lrgc/common/params_io.h>

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/format.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <cstdio>
#include <set>
#include <utility>
#include <algorithm>

namespace lrgc
{
void TMapBuilderParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
										   const std::string& s)
{
	rejectUnknownKeys(TMapBuilderParams(), c, s);
	keyframe_distance_m = readDouble(c, s, "keyframe_distance_m", keyframe_distance_m);
	keyframe_angle = readDegrees(c, s, "keyframe_angle_deg", keyframe_angle);
	min_scan_points = readCount(c, s, "min_scan_points", min_scan_points);
	grid_resolution_m = readDouble(c, s, "grid_resolution_m", grid_resolution_m);
	loop_closing = readBool(c, s, "loop_closing", loop_closing);
	final_optimization = readBool(c, s, "final_optimization", final_optimization);
	scan_sweep_time_s = readDouble(c, s, "scan_sweep_time_s", scan_sweep_time_s);
	laser_label = readString(c, s, "laser_label", laser_label);
	min_range_m = readDouble(c, s, "min_range_m", min_range_m);
	max_range_m = readDouble(c, s, "max_range_m", max_range_m);
	requireParam(scan_sweep_time_s >= 0 && scan_sweep_time_s < 1, s, "scan_sweep_time_s",
				 "must be in [0, 1) s");
	requireParam(min_range_m >= 0, s, "min_range_m", "must be >= 0 m (0: no lower limit)");
	requireParam(
		max_range_m == 0 || max_range_m > min_range_m, s, "max_range_m",
		mrpt::format("must be 0 (no upper limit) or above min_range_m = %g m", min_range_m));
	requireParam(keyframe_distance_m > 0, s, "keyframe_distance_m", "must be > 0");
	requireParam(keyframe_angle > 0, s, "keyframe_angle_deg", "must be > 0");
	requireParam(min_scan_points >= 3, s, "min_scan_points", "must be >= 3");
	requireParam(grid_resolution_m >= 0.005 && grid_resolution_m <= 1, s, "grid_resolution_m",
				 "must be in [0.005, 1] m");
}

void TMapBuilderParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
										 const std::string& s) const
{
	writeValue(c, s, "keyframe_distance_m", keyframe_distance_m,
			   "[m] A scan becomes a keyframe (graph node) after this much travel");
	writeDegrees(c, s, "keyframe_angle_deg", keyframe_angle,
				 "[deg] ... or after this much turn");
	writeValue(c, s, "min_scan_points", uint64_t(min_scan_points),
			   "Scans with fewer valid returns are skipped (with a warning)");
	writeValue(c, s, "grid_resolution_m", grid_resolution_m,
			   "[m] Cell size of the exported occupancy grid map");
	writeValue(c, s, "loop_closing", loop_closing,
			   "Global correlation and loop closing (false: local registration only)");
	writeValue(c, s, "final_optimization", final_optimization,
			   "Optimise the whole graph once more at the end of the run");
	writeValue(c, s, "scan_sweep_time_s", scan_sweep_time_s,
			   "[s] Laser's first beam to last (SICK LMS 2xx: 0.0067): scans are de-skewed by "
			   "the motion over it; 0: off, or estimated online if [SweepEstimator] enabled");
	writeValue(c, s, "laser_label", laser_label,
			   "sensorLabel of the laser to map (CARMEN: LASER = FLASER, REAR_LASER = RLASER); "
			   "empty: the first seen (lrgc-slam --laser)");
	writeValue(
		c, s, "min_range_m", min_range_m,
		"[m] Readings of that laser below this are dropped (the robot's own posts); 0: none");
	writeValue(c, s, "max_range_m", max_range_m,
			   "[m] Readings above this are dropped; 0: only the sensor's own maximum range");
}

namespace
{
/** Every stage's section with its parameters, in the order they are saved: the one list
 * that load, save and sectionNames() walk. */
template <class Params, class Stage>
std::vector<std::pair<const char*, Stage*>> stages(Params& p)
{
	return {{"MapBuilder", &p.builder},           {"KeyframeReuse", &p.reuse},
			{"MotionPredictor", &p.motion},       {"SweepEstimator", &p.sweep},
			{"ScanMatcher", &p.matcher},          {"LocalRegistration", &p.local},
			{"PoseGraphOptimizer", &p.optimizer}, {"LoopCloser", &p.loop},
			{"PatchCorrelator", &p.correlator},   {"RevisitLinker", &p.revisits}};
}
}  // namespace

const std::vector<std::string>& TLRGCParams::sectionNames()
{
	static const std::vector<std::string> names = []
	{
		TLRGCParams p;
		std::vector<std::string> out;
		for (const auto& [name, stage] : stages<TLRGCParams, mrpt::config::CLoadableOptions>(p))
			out.push_back(name);
		return out;
	}();
	return names;
}

void rejectUnknownSections(const mrpt::config::CConfigFileBase& c,
						   const std::vector<std::string>& allowed)
{
	std::vector<std::string> sections;
	c.getAllSections(sections);
	const std::set<std::string> known(allowed.begin(), allowed.end());
	for (const auto& sec : sections)
		if (!sec.empty() && !known.count(sec))
			THROW_EXCEPTION_FMT("Unknown section [%s] in the configuration", sec.c_str());
}

const std::vector<TRenamedKey>& TLRGCParams::renamedKeys()
{
	static const std::vector<TRenamedKey> renamed = {
		{"MapBuilder", "keyframe_distance", "keyframe_distance_m", ""},
		{"MapBuilder", "grid_resolution", "grid_resolution_m", ""},
		{"MapBuilder", "scan_sweep_time", "scan_sweep_time_s", ""},
		{"MapBuilder", "min_range", "min_range_m", ""},
		{"MapBuilder", "max_range", "max_range_m", ""},
		{"KeyframeReuse", "min_inliers", "min_inlier_fraction", ""},
		{"MotionPredictor", "sigma_floor_xy", "sigma_floor_xy_m", ""},
		{"MotionPredictor", "k_xy_per_m", "k_xy_m_per_m", ""},
		{"MotionPredictor", "k_xy_per_rad", "k_xy_m_per_rad", ""},
		{"MotionPredictor", "k_phi_per_m", "k_phi_rad_per_m", ""},
		{"MotionPredictor", "k_phi_per_rad", "k_phi_rad_per_rad", ""},
		{"MotionPredictor", "noise_correlation_length", "noise_correlation_length_m", ""},
		{"MotionPredictor", "cv_sigma_xy", "cv_sigma_xy_m", ""},
		{"SweepEstimator", "max_sweep_time", "max_sweep_time_s", ""},
		{"SweepEstimator", "min_rate_change_deg", "min_rate_change_deg_per_s", ""},
		{"SweepEstimator", "max_std", "max_std_s", ""},
		{"ScanMatcher", "max_correspondence_dist", "max_correspondence_dist_m", ""},
		{"ScanMatcher", "ref_resolution", "ref_resolution_m", ""},
		{"ScanMatcher", "normal_radius", "normal_radius_m", ""},
		{"ScanMatcher", "max_rms_residual", "max_rms_residual_m", ""},
		{"ScanMatcher", "min_residual_std", "min_residual_std_m", ""},
		{"ScanMatcher", "unobservable_std", "unobservable_std_m", ""},
		{"LocalRegistration", "min_link_inliers", "min_link_inlier_fraction", ""},
		{"LocalRegistration", "link_floor_xy", "link_floor_xy_m", ""},
		{"LocalRegistration", "glitch_min_gap", "glitch_min_gap_s", ""},
		{"LocalRegistration", "patch_link_floor_xy", "patch_link_floor_xy_m", ""},
		{"LoopCloser", "old_map_exclusion", "old_map_exclusion_keyframes", ""},
		{"LoopCloser", "overlap_radius", "overlap_radius_m", ""},
		{"LoopCloser", "max_window_xy", "max_window_xy_m", ""},
		{"LoopCloser", "max_window_theta_deg", "max_window_phi_deg", ""},
		{"LoopCloser", "confirm_above_sigma", "confirm_above_sigma_m", ""},
		{"LoopCloser", "match_ref_resolution", "match_ref_resolution_m", ""},
		{"LoopCloser", "patch_max_range", "patch_max_range_m", ""},
		{"LoopCloser", "result_delay", "result_delay_keyframes", ""},
		{"LoopCloser", "max_backlog", "max_backlog_keyframes", ""},
		{"LoopCloser", "link_floor_xy", "link_floor_xy_m", ""},
		{"LoopCloser", "apply_when_ready", "",
		 "offline runs apply each loop result at its fixed keyframe; lrgc-slam --live takes "
		 "them when ready as [LiveMapping] loop_results_when_ready says"},
		{"PatchCorrelator", "resolution", "resolution_m", ""},
		{"PatchCorrelator", "blur_sigma", "blur_sigma_m", ""},
		{"PatchCorrelator", "max_std_xy", "max_std_xy_m", ""},
		{"PatchCorrelator", "max_std_theta_deg", "max_std_phi_deg", ""},
		{"PatchCorrelator", "cluster_radius", "cluster_radius_m", ""},
		{"PatchCorrelator", "cluster_radius_deg", "cluster_radius_phi_deg", ""},
		{"RevisitLinker", "radius", "radius_m", ""},
		{"RevisitLinker", "max_heading_deg", "max_phi_deg", ""},
		{"RevisitLinker", "min_inliers", "min_inlier_fraction", ""},
		{"RevisitLinker", "prior_std_xy", "prior_std_xy_m", ""}};
	return renamed;
}

std::vector<std::string> TLRGCParams::loadReportingRenames(
	const mrpt::config::CConfigFileBase& c, const std::string& prefix)
{
	std::vector<std::string> warnings;
	const mrpt::config::CConfigFileMemory current =
		withCurrentKeys(c, renamedKeys(), prefix, warnings);
	for (const auto& [name, stage] : stages<TLRGCParams, mrpt::config::CLoadableOptions>(*this))
		stage->loadFromConfigFile(current, prefix + name);
	requireParam(
		loop.old_map_exclusion_keyframes >
			std::max(local.window_size, local.laser_only_window_size),
		prefix + "LoopCloser", "old_map_exclusion_keyframes",
		mrpt::format(
			"%zu must exceed [LocalRegistration] window_size and laser_only_window_size, which "
			"are %zu and %zu (the paper's m > K)",
			loop.old_map_exclusion_keyframes, local.window_size, local.laser_only_window_size));
	return warnings;
}

void TLRGCParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
									 const std::string& prefix)
{
	for (const auto& w : loadReportingRenames(c, prefix))
		std::fprintf(stderr, "lrgc: warning: %s\n", w.c_str());
}

void TLRGCParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
								   const std::string& prefix) const
{
	for (const auto& [name, stage] :
		 stages<const TLRGCParams, const mrpt::config::CLoadableOptions>(*this))
		stage->saveToConfigFile(c, prefix + name);
}

}  // namespace lrgc
