#include <lrgc/loop_closing/LoopCloserParams.h>
#include <lrgc/common/params_io.h>
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/format.h>

namespace lrgc
{
namespace
{
// [LoopCloser]'s keys of the re-match's check against the closure's solve.
void loadRematchCheck(const mrpt::config::CConfigFileBase& c, const std::string& s,
					  TLoopCloserParams& p)
{
	p.rematch_solve_std_m = readDouble(c, s, "rematch_solve_std_m", p.rematch_solve_std_m);
	requireParam(p.rematch_solve_std_m >= 0, s, "rematch_solve_std_m", "must be >= 0");
	p.rematch_solve_std = readDegrees(c, s, "rematch_solve_std_deg", p.rematch_solve_std);
	requireParam(p.rematch_solve_std >= 0, s, "rematch_solve_std_deg", "must be >= 0");
}

// [LoopCloser]'s keys of which points the patch keeps.
void savePatchPoints(mrpt::config::CConfigFileBase& c, const std::string& s,
					 const TLoopCloserParams& p)
{
	writeValue(c, s, "patch_max_range_m", p.patch_max_range_m,
			   "[m] Patch points farther than this from the newest keyframe are left out of "
			   "the correlation");
	writeValue(c, s, "patch_far_gap_m", p.patch_far_gap_m,
			   "[m] Old keyframes' far points seen through a gap this deep: left out");
}

void saveRematchCheck(mrpt::config::CConfigFileBase& c, const std::string& s,
					  const TLoopCloserParams& p)
{
	writeValue(c, s, "rematch_solve_std_m", p.rematch_solve_std_m,
			   "[m] The closure's solve's own error a re-match is allowed, in x and y");
	writeDegrees(c, s, "rematch_solve_std_deg", p.rematch_solve_std,
				 "[deg] The closure's solve's own error a re-match is allowed, in heading");
}
}  // namespace

void TLoopCloserParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
										   const std::string& s)
{
	rejectUnknownKeys(TLoopCloserParams(), c, s);
	old_map_exclusion_keyframes =
		readCount(c, s, "old_map_exclusion_keyframes", old_map_exclusion_keyframes);
	patch_min_keyframes = readCount(c, s, "patch_min_keyframes", patch_min_keyframes);
	patch_keyframes_per_m = readDouble(c, s, "patch_keyframes_per_m", patch_keyframes_per_m);
	patch_keyframes_per_ambiguity =
		readCount(c, s, "patch_keyframes_per_ambiguity", patch_keyframes_per_ambiguity);
	patch_grown_min_new_cells =
		readDouble(c, s, "patch_grown_min_new_cells", patch_grown_min_new_cells);
	requireParam(patch_grown_min_new_cells >= 0, s, "patch_grown_min_new_cells",
				 "must be >= 0");
	patch_max_travel_m = readDouble(c, s, "patch_max_travel_m", patch_max_travel_m);
	requireParam(patch_max_travel_m >= 0, s, "patch_max_travel_m", "must be >= 0");
	gate_sigma = readDouble(c, s, "gate_sigma", gate_sigma);
	gate_fuse_links = readBool(c, s, "gate_fuse_links", gate_fuse_links);
	gate_drift_xy_m2_per_m = readDouble(c, s, "gate_drift_xy_m2_per_m", gate_drift_xy_m2_per_m);
	requireParam(gate_drift_xy_m2_per_m >= 0, s, "gate_drift_xy_m2_per_m", "must be >= 0");
	overlap_radius_m = readDouble(c, s, "overlap_radius_m", overlap_radius_m);
	window_sigmas = readDouble(c, s, "window_sigmas", window_sigmas);
	max_window_xy_m = readDouble(c, s, "max_window_xy_m", max_window_xy_m);
	max_window_phi = readDegrees(c, s, "max_window_phi_deg", max_window_phi);
	confirm_above_sigma_m = readDouble(c, s, "confirm_above_sigma_m", confirm_above_sigma_m);
	requireParam(confirm_above_sigma_m >= 0, s, "confirm_above_sigma_m", "must be >= 0");
	far_search_every_keyframes =
		readCount(c, s, "far_search_every_keyframes", far_search_every_keyframes);
	far_window_xy_m = readDouble(c, s, "far_window_xy_m", far_window_xy_m);
	requireParam(far_window_xy_m > 0 && far_window_xy_m <= 1000, s, "far_window_xy_m",
				 "must be in (0, 1000] m");
	far_resolution_m = readDouble(c, s, "far_resolution_m", far_resolution_m);
	requireParam(far_resolution_m >= 0.01 && far_resolution_m <= 1, s, "far_resolution_m",
				 "must be in [0.01, 1] m");
	far_candidates = readCount(c, s, "far_candidates", far_candidates);
	requireParam(far_candidates >= 1, s, "far_candidates", "must be >= 1");
	consistent_chi2 = readDouble(c, s, "consistent_chi2", consistent_chi2);
	check_every = readCount(c, s, "check_every", check_every);
	known_ground_check_every =
		readCount(c, s, "known_ground_check_every", known_ground_check_every);
	gate_reuse_keyframes = readCount(c, s, "gate_reuse_keyframes", gate_reuse_keyframes);
	match_ref_resolution_m = readDouble(c, s, "match_ref_resolution_m", match_ref_resolution_m);
	requireParam(match_ref_resolution_m >= 0, s, "match_ref_resolution_m", "must be >= 0");
	patch_max_range_m = readDouble(c, s, "patch_max_range_m", patch_max_range_m);
	patch_far_gap_m = readDouble(c, s, "patch_far_gap_m", patch_far_gap_m);
	requireParam(patch_far_gap_m >= 0, s, "patch_far_gap_m", "must be >= 0");
	loadRematchCheck(c, s, *this);
	corridor_ridges = readBool(c, s, "corridor_ridges", corridor_ridges);
	attempt_stride = readDouble(c, s, "attempt_stride", attempt_stride);
	requireParam(attempt_stride >= 0, s, "attempt_stride", "must be >= 0");
	background = readBool(c, s, "background", background);
	result_delay_keyframes = readCount(c, s, "result_delay_keyframes", result_delay_keyframes);
	worker_budget_ms = readDouble(c, s, "worker_budget_ms", worker_budget_ms);
	requireParam(worker_budget_ms >= 0, s, "worker_budget_ms", "must be >= 0");
	worker_budget_span = readDouble(c, s, "worker_budget_span", worker_budget_span);
	requireParam(worker_budget_span >= 0, s, "worker_budget_span", "must be >= 0");
	max_backlog_keyframes = readCount(c, s, "max_backlog_keyframes", max_backlog_keyframes);
	link_noise.load(c, s, "");
	requireParam(patch_max_range_m > 0, s, "patch_max_range_m", "must be > 0");
	requireParam(patch_min_keyframes >= 1 && patch_min_keyframes <= old_map_exclusion_keyframes,
				 s, "patch_min_keyframes",
				 mrpt::format("%zu must be in [1, old_map_exclusion_keyframes]; "
							  "old_map_exclusion_keyframes is %zu",
							  patch_min_keyframes, old_map_exclusion_keyframes));
	requireParam(patch_keyframes_per_m >= 0, s, "patch_keyframes_per_m", "must be >= 0");
	requireParam(gate_sigma > 0, s, "gate_sigma", "must be > 0");
	requireParam(overlap_radius_m >= 0, s, "overlap_radius_m", "must be >= 0");
	requireParam(window_sigmas > 0, s, "window_sigmas", "must be > 0");
	requireParam(max_window_xy_m > 0, s, "max_window_xy_m", "must be > 0");
	requireParam(max_window_phi > 0 && max_window_phi <= M_PI, s, "max_window_phi_deg",
				 "must be in (0, 180]");
	requireParam(consistent_chi2 > 0, s, "consistent_chi2", "must be > 0");
	requireParam(check_every >= 1, s, "check_every", "must be >= 1");
	requireParam(known_ground_check_every >= 1, s, "known_ground_check_every", "must be >= 1");
	requireParam(gate_reuse_keyframes <= old_map_exclusion_keyframes, s, "gate_reuse_keyframes",
				 mrpt::format("%zu must be <= old_map_exclusion_keyframes (%zu)",
							  gate_reuse_keyframes, old_map_exclusion_keyframes));
}

namespace
{
// [LoopCloser]'s far search keys, in saveToConfigFile's order.
void saveFarSearch(mrpt::config::CConfigFileBase& c, const std::string& s,
				   const TLoopCloserParams& p)
{
	writeValue(
		c, s, "far_search_every_keyframes", uint64_t(p.far_search_every_keyframes),
		"While the window is capped and finds no loop, search the whole old map (every "
		"heading, coarse grid) every this many checks, on a lane of its own that never moves "
		"the near searches' schedule; a place it proposes closes a loop only once a later "
		"patch confirms it (0: never)");
	writeValue(c, s, "far_window_xy_m", p.far_window_xy_m,
			   "[m] Least half-window of that far search (window_sigmas sigma when larger, cut "
			   "at the old map's extent), and the width of the rings it proposes places in");
	writeValue(
		c, s, "far_resolution_m", p.far_resolution_m,
		"[m] Its grid cell (it proposes; the confirming searches run at full resolution)");
	writeValue(c, s, "far_candidates", uint64_t(p.far_candidates),
			   "Distinct places it proposes per ring of far_window_xy_m, at most");
}
}  // namespace

void TLoopCloserParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
										 const std::string& s) const
{
	writeValue(c, s, "old_map_exclusion_keyframes", uint64_t(old_map_exclusion_keyframes),
			   "m: newest keyframes left out of the old map (m > K)");
	writeValue(c, s, "patch_min_keyframes", uint64_t(patch_min_keyframes),
			   "Map patch size (keyframes) at zero uncertainty");
	writeValue(
		c, s, "patch_keyframes_per_m", patch_keyframes_per_m,
		"[1/m] Patch growth per metre of position std (capped at old_map_exclusion_keyframes)");
	writeValue(c, s, "patch_keyframes_per_ambiguity", uint64_t(patch_keyframes_per_ambiguity),
			   "Keyframes the patch tried after an ambiguous one grows by per such check since "
			   "the last closure (capped at old_map_exclusion_keyframes; 0: off)");
	writeValue(c, s, "patch_grown_min_new_cells", patch_grown_min_new_cells,
			   "Share of the first patch's cells the grown one must add (0: always tried)");
	writeValue(
		c, s, "patch_max_travel_m", patch_max_travel_m,
		"[m] A patch spans at most this much path (at least patch_min_keyframes); 0: no cap");
	writeValue(c, s, "gate_sigma", gate_sigma,
			   "Mahalanobis gate on old poses' position relative to the current one");
	writeValue(c, s, "gate_fuse_links", gate_fuse_links,
			   "The gate walks each step once, its parallel links' information added across "
			   "link types (false: by its single most certain link)");
	writeValue(c, s, "gate_drift_xy_m2_per_m", gate_drift_xy_m2_per_m,
			   "[m^2/m] Position variance the gate adds per metre of each step (drift scan "
			   "matching's covariance does not hold)");
	writeValue(c, s, "overlap_radius_m", overlap_radius_m,
			   "[m] Poses closer than this can see the same walls");
	writeValue(c, s, "window_sigmas", window_sigmas,
			   "Correlation search half-window, in position/heading std devs");
	writeValue(c, s, "max_window_xy_m", max_window_xy_m,
			   "[m] Cap of the translational search half-window");
	writeDegrees(c, s, "max_window_phi_deg", max_window_phi,
				 "[deg] Cap of the rotational search half-window");
	writeValue(c, s, "confirm_above_sigma_m", confirm_above_sigma_m,
			   "[m] Gate std above which a loop is closed only when a second, independent "
			   "match agrees (0: never)");
	saveFarSearch(c, s, *this);
	writeValue(c, s, "consistent_chi2", consistent_chi2,
			   "[chi2, 3 dof] A loop link this consistent is added without a full solve");
	writeValue(c, s, "check_every", uint64_t(check_every),
			   "Look for a loop every this many keyframes");
	writeValue(c, s, "known_ground_check_every", uint64_t(known_ground_check_every),
			   "After a check that added a loop link agreeing with the map (no solve), look "
			   "again only every this many keyframes");
	writeValue(c, s, "gate_reuse_keyframes", uint64_t(gate_reuse_keyframes),
			   "[keyframes] The gate's whole-graph propagation serves this many later "
			   "keyframes while the graph behind it is unchanged (0: every keyframe)");
	writeValue(c, s, "match_ref_resolution_m", match_ref_resolution_m,
			   "[m] Voxel side of the loop link's reference cloud, built from every old scan "
			   "around (0: [ScanMatcher] ref_resolution_m)");
	savePatchPoints(c, s, *this);
	saveRematchCheck(c, s, *this);
	writeValue(c, s, "corridor_ridges", corridor_ridges,
			   "The near search takes look-alikes on one straight line through its best pose "
			   "as a corridor's slide, carried by the loop link's covariance");
	writeValue(c, s, "attempt_stride", attempt_stride,
			   "While the patch is grown, correlate once every attempt_stride * (patch - "
			   "patch_min_keyframes) checks (0: every check)");
	writeValue(c, s, "background", background,
			   "Loop closing on a worker thread while scans are registered (false: on the "
			   "mapping thread; same map)");
	writeValue(c, s, "result_delay_keyframes", uint64_t(result_delay_keyframes),
			   "[keyframes] A loop search started at keyframe k is applied at k + this "
			   "(deterministic: the mapping thread waits there if needed)");
	writeValue(
		c, s, "worker_budget_ms", worker_budget_ms,
		"[ms per keyframe] A result is applied where a modelled worker doing this much work "
		"per keyframe finishes it (deterministic; 0: at k + result_delay_keyframes)");
	writeValue(
		c, s, "worker_budget_span", worker_budget_span,
		"[keyframe spacings] A keyframe s spacings of travel after the previous one grants "
		"the modelled worker worker_budget_ms * max(1, s / this), at most 4x; 0: off");
	writeValue(
		c, s, "max_backlog_keyframes", uint64_t(max_backlog_keyframes),
		"[keyframes] Searches are deferred while the modelled worker is more than this many "
		"keyframes' budget behind");
	link_noise.save(c, s, "", "every loop link (scans minutes apart: moved objects)");
}

}  // namespace lrgc
