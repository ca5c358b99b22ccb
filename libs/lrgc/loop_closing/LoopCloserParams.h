/* Section [LoopCloser]: the parameters of CLoopCloser, apart from the class so that the
 * map builder's public header (MapBuilderParams.h) needs none of the stage's internals. */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/core/bits_math.h>
#include <lrgc/pose_graph/LinkNoise.h>

#include <cmath>
#include <cstddef>
#include <string>

namespace lrgc
{
struct TLoopCloserParams : public mrpt::config::CLoadableOptions
{
	size_t old_map_exclusion_keyframes =
		40;                            //!< m: newest keyframes left out of the old map (m > K)
	size_t patch_min_keyframes = 10;   //!< patch size at zero uncertainty
	double patch_keyframes_per_m = 8;  //!< patch growth per metre of position std [1/m]
	/** Keyframes the grown patch adds to the sigma's for each check whose sigma patch was
	 * rejected as ambiguous since the last closure (paper 2.4: a patch must be distinctive
	 * within its window; where it is not, a larger one may be), the patch at most
	 * old_map_exclusion_keyframes. The grown patch is a second try in the same check, made
	 * only after the sigma's patch was rejected as ambiguous; the sigma's is always tried
	 * first. The calibrated gate's small sigma makes the sigma's patch 10-18 keyframes where
	 * railings and glass need more (GlassBuilding 16 / 21 without, 21 / 21 with); tried
	 * first instead (stop 46), the grown patch spanned KeyframeReuse's slipping corridor and
	 * PerceptualAliasing's drifted rooms and scored wrong where the sigma's closes
	 * (doc/generalisation.md, glass_stress). 0: off. */
	size_t patch_keyframes_per_ambiguity = 10;
	/** The grown patch is correlated only when it adds at least this share of the sigma's
	 * patch's cells (distinct cells of [PatchCorrelator] resolution_m within
	 * patch_max_range_m of the newest keyframe) to it; with fewer it is the same correlation
	 * again, as dear as the first and with its verdict. Where keyframes lie 1-1.5 m apart
	 * (the harsh sparse variants) the keyframes added lie mostly beyond patch_max_range_m:
	 * on MIT Killian's b80 variant 61 of 70 grown patches added under 10 % (most 0-4 %), 70
	 * of 71 failed the filters again, and the modelled worker shed 86-120 searches
	 * (doc/generalisation.md, "A second try the worker can afford"). The grown patches that
	 * passed the filters on the dense, sparse and b80 logs added 34-198 %. 0: always tried. */
	double patch_grown_min_new_cells = 0.2;
	/** [m] A patch spans at most this much of the robot's path (but at least
	 * patch_min_keyframes keyframes); 0: no cap. Dense logs' keyframes lie 0.3-0.5 m apart,
	 * so their patches (10-40 keyframes: 3-20 m) rarely reach it; sparse scans' lie 1 m
	 * apart. */
	double patch_max_travel_m = 24;
	double gate_sigma = 3.0;  //!< Mahalanobis gate on the candidates' position [-]
	/** The gate's propagation walks each step between two keyframes once, with the
	 * information of its parallel links added across link types (odometry, scan matching,
	 * loop links are independent sensors; of the links of one type, which share their scans,
	 * the most certain in position stands for it), not by whichever single link places the
	 * node with the smaller position variance (UncertaintyPropagation.h, TStepModel). With
	 * single links the odometry link's 1.7 deg a step compounds: one lap of the glass atrium
	 * (392 m) gave the start a std of 24 / 50 m and 33 deg where the online map was 0.4 m and
	 * 0.6 deg off. With gate_drift_xy_m2_per_m 5e-4 the gate is calibrated against the truth
	 * on every log measured; its smaller sigma also shrinks the patch (patch_keyframes_per_m),
	 * which patch_keyframes_per_ambiguity makes up for among railings and glass
	 * (doc/generalisation.md, glass_stress). false: the single most certain link. */
	bool gate_fuse_links = true;
	/** [m^2 per m] Position variance the gate adds to each step per metre of its length, in
	 * both axes of the step's frame: the drift scan matching's covariance does not hold (a
	 * corridor's slide along itself, a scale error). With fused links and none, the gate
	 * claimed 0.3 m where MIT Killian's return was 1.9 m off along its corridor; 5e-4 (a
	 * random walk of 2.2 cm per sqrt(m)) put the true place inside the window at 99.3-100 %
	 * of the checks at a revisit on the eight shared logs and the glass worlds. 0: none (for
	 * single links, whose gate is already wider than the drift). */
	double gate_drift_xy_m2_per_m = 0.0005;
	double overlap_radius_m = 3.0;  //!< [m] poses this close can see the same walls
	double window_sigmas = 3.0;     //!< search half-window in standard deviations [-]
	double max_window_xy_m = 15.0;  //!< [m] cap of the translational search half-window
	double max_window_phi = mrpt::DEG2RAD(30.0);  //!< [rad] (key max_window_phi_deg)
	/** [m] When the gate's largest position std exceeds this, an accepted match is only held:
	 * its link is added when a later match, from a patch that shares no keyframe with it,
	 * agrees with it (both imply the same pose of the newer node). With so large an
	 * uncertainty the back-end cannot tell a false link from a true one (the graph absorbs
	 * either), and a large window holds look-alikes. A held match that finds no agreeing one
	 * within 2 old_map_exclusion_keyframes keyframes is dropped. 0: never hold. */
	double confirm_above_sigma_m = 0;
	/** Beyond the window (issue 28: a revisit the drift put tens of metres from the map).
	 * While the window is capped (window_sigmas sigma beyond max_window_xy_m or
	 * max_window_phi_deg, so the true place may lie outside it) and found no loop, every this
	 * many such checks since the last far search started (so one starts as soon as the last
	 * ends when that many have passed; none is dropped for its age, one still checking its
	 * places when the next is due is superseded by it, counted merged or dropped with its
	 * place in stats.json), on a lane of its own (LoopCloser_lane.cpp), the patch is correlated
	 * with the whole old map within window_sigmas sigma (far_window_xy_m below) at every
	 * heading on a coarse grid (the paper's global correlation, section 2.3, by branch and
	 * bound); its far_candidates best distinct poses per ring are each searched again at full
	 * resolution in a small window with the three filters and scan-matched. Those that pass are
	 * held; a loop is closed only when a later patch, sharing no keyframe with theirs, confirms
	 * exactly one of them. 0: never. The lane is a second modelled worker with the near
	 * worker's budget, its work counted apart, its steps on a thread of their own: the near
	 * searches' schedule is the same with it or without, so the far search changes a map only
	 * by a loop it closes. 25 closes the hall loops of tests/large_loop_test.cpp (30 m / 87
	 * deg and 117 m / 93 deg off at the return, the latter within 55 m of return) with the
	 * defaults; on the shared logs only Killian's gate reaches 4 caps: 14 far searches, none
	 * closes (the near search closes that loop later: 0.0290 m as with main's one far
	 * closure), the other four logs byte for byte as with 0 (doc/generalisation.md).
	 */
	size_t far_search_every_keyframes = 25;
	/** [m] The far search's least half-window, and its rings' width. The window is
	 * window_sigmas sigma of the gate's position when that is larger, cut at the old map's
	 * extent: a revisit stands where the drift put it (the held-out long-range log: 126 m
	 * away, median). Its places are proposed ring by ring (ring r: the newest keyframe r to
	 * r + 1 times this from where the map has it, in x or y), far_candidates per ring, so that
	 * look-alikes in a wide window do not crowd the true place out (with one list over 250 m
	 * Killian lost its one far closure). 100 closes a 600 m loop 117 m off at the return
	 * (LargeLoop.aReturnMoreThan100mOffClosesWithin55m). */
	double far_window_xy_m = 100.0;
	/** [m] The far search's grid cell: it only proposes places for the full-resolution
	 * search; its blur is at least a cell. 0.4 costs 2.4 times less than 0.2 on the hall loop.
	 */
	double far_resolution_m = 0.4;
	size_t far_candidates = 8;  //!< distinct places the far search proposes per ring, at most
	double consistent_chi2 = 11.34;  //!< [chi2, 3 dof] a link agreeing this well needs no solve
	/** Look for a loop every this many keyframes. 2 halves the loop closer's work, but
	 * moved Killian's error from 0.029 to 0.030-0.035 m (doc/generalisation.md). */
	size_t check_every = 1;
	/** After a check that added a loop link agreeing with the map (no solve needed: the
	 * robot drives on ground it mapped before, and the map holds there), look again only
	 * every this many keyframes, until a check adds no such link. 2 halved Intel's loop
	 * links (1356 -> 708) and its worker's CPU (17.2 -> 9.2 s) at the same error, but moved
	 * Killian's from 0.0289 to 0.0303 m (doc/generalisation.md): not a default. */
	size_t known_ground_check_every = 1;
	/** The gate's propagation over the whole graph, done at an anchor keyframe a, serves the
	 * next this many keyframes n while the graph behind a is unchanged (no pose of the old
	 * map moved, no loop link added, no link reaching further back than a -
	 * old_map_exclusion_keyframes): (n <- v) = (n <- a) (+) (a <- v), so a keyframe costs a
	 * pass over the labels instead of a Dijkstra over every link. At most
	 * old_map_exclusion_keyframes; 0: propagate at every keyframe. */
	size_t gate_reuse_keyframes = 39;
	/** [m] Voxel side of the link's reference cloud (step 3), built from every old scan
	 * around: many views fill the walls' voxels densely, and the line fits' cost grows with
	 * the voxels per neighbourhood. 0: [ScanMatcher] ref_resolution_m. */
	double match_ref_resolution_m = 0.03;
	/** [m] Patch points farther from the newest keyframe are left out of the correlation:
	 * the heading step is resolution / patch radius, so 40 m returns (ACES) would need
	 * ~900 headings over +-30 deg; far returns are also the noisiest. */
	double patch_max_range_m = 12.0;
	/** [m] An older keyframe's patch point it saw farther than patch_max_range_m away is left
	 * out where a beam within two of it returned more than this nearer: seen through a gap
	 * (between a railing's posts, past a glass pane's frame), where the far side's returns,
	 * mixed pixels and panes' returns are what no keyframe near the place sees alike (the
	 * glass atrium's first-return false closure, CLoopCloser::patchPoints). 0: kept. */
	double patch_far_gap_m = 0.5;
	/** A re-match after a closure (CLoopCloser::rematch) is refused where it disagrees with the
	 * closure's solve, read in its old keyframe's axes with the solve's own error between the
	 * two keyframes added: this std [m] in x and y, rematch_solve_std [rad] in heading (key
	 * rematch_solve_std_deg). */
	double rematch_solve_std_m = 0.15;
	double rematch_solve_std = mrpt::DEG2RAD(1.0);  //!< [rad] (key rematch_solve_std_deg)
	/** The near search's correlation takes rivals on one straight line through its best pose
	 * (the same heading and place across it, inside the window) as the best peak's own: a
	 * corridor's slide, whose look-alikes agree on all but the position along it. The loop
	 * link then carries that doubt in its covariance (CPatchCorrelator::setStraightRidges,
	 * CLoopCloser::carryRidge). Only a ridge whose first step reaches the window's centre (the
	 * gate's prediction) within a cluster radius is taken (rival_search.cpp,
	 * ridgeReachesCentre): without that, a ridge 8.9 m from the prediction put a loop link
	 * 5.6 m along a corridor from the truth on SparseScans.TurnsOfEightyDegrees. On, the glass
	 * atrium closes 72 / 73 / 72 / 74 of 79 places (seeds 1-4; off 71 / 70 / 70 / 69), no false
	 * link, and the e2e tests of stop 49 pass. Against it: the harsh sparse Intel b80 s2 maps
	 * worse on two worker schedules of three (0.068 -> 0.089 m, schedule chaos: no ridge link
	 * in it). LiveSickSavedMap.ContinuesASavedMapWithLiveScans's failures on a loaded machine
	 * are the scans' arrival stamps', the same with it off (doc/generalisation.md, "The live
	 * test and the failed ridge match"). */
	bool corridor_ridges = true;
	/** While the patch is larger than patch_min_keyframes (large uncertainty), correlate only
	 * once every attempt_stride * (patch - patch_min_keyframes) checks: consecutive large
	 * patches are nearly the same evidence, and a large window is the costly case (Killian:
	 * 1357 -> 146 correlations at the window cap, same error). 0: every check. 0.25 -> 0.5
	 * cut Killian's worker CPU 45 -> 31 s (correlation 27.8 -> 16.0 s) and ACES's 7.0 ->
	 * 4.6 s at the same errors; 1.0 missed the loops of the synthetic rings (the patch
	 * grows past the closing place between two attempts). */
	double attempt_stride = 0.5;
	/** Run loop closing on a worker thread (CLoopClosingWorker) while the mapping thread goes
	 * on registering scans; false: on the mapping thread (the same map, without the overlap).
	 */
	bool background = true;
	/** A loop search started at keyframe k is applied to the map at keyframe k +
	 * result_delay_keyframes (the mapping thread waits there only if the worker is not done):
	 * the result never depends on the machine's speed. Searches start at every keyframe
	 * (check_every) and queue up on the worker; results are applied in order. 0: applied at
	 * once. */
	size_t result_delay_keyframes = 1;
	/** [ms of the reference machine per keyframe] With this > 0, a result is applied at the
	 * keyframe where a modelled worker finishes it (not before k + result_delay_keyframes): a
	 * worker that does this much of the work modelled by TLoopWork per keyframe, one job after
	 * the other. A whole-graph closure of a large map then lands some hundred keyframes later
	 * instead of stalling the mapping thread at k + result_delay_keyframes; the schedule is
	 * still a function of the log alone. 0: every result at k + result_delay_keyframes. */
	double worker_budget_ms = 5;
	/** [keyframe spacings] The budget follows the data: a keyframe taken after the robot
	 * travelled s keyframe spacings since the previous one (s = max(path / keyframe_distance_m,
	 * turn / keyframe_angle), summed over the scans between) lets the modelled worker do
	 * worker_budget_ms * max(1, s / this) of work (at most 4 worker_budget_ms;
	 * CLoopClosingWorker). A dense log takes a keyframe just past one spacing (s 1.0-1.8 on
	 * Intel, ACES, MIT-CSAIL, Killian) and keeps worker_budget_ms per keyframe; a sparse one,
	 * where one scan step spans 3-5 spacings, gets the work of the keyframes it stands for. A
	 * stop adds no travel, so it grants nothing extra. 0: worker_budget_ms per keyframe. */
	double worker_budget_span = 1.5;
	/** [keyframes] When the modelled worker is more than this many keyframes' budget
	 * (this * worker_budget_ms) behind, a job only brings the worker's graph up to date and
	 * defers its search, unless the last search ran patch_min_keyframes keyframes ago:
	 * searches are thinned, never stopped, and a deferred search is merged into the next
	 * search, whose patch holds its keyframe (its place is searched). The worker's work
	 * stays bounded by its budget. Only
	 * with worker_budget_ms > 0. Live runs (apply_when_ready) use neither: results are
	 * taken when ready and no search is skipped. 150: with 15-keyframe windows, 300 let
	 * Intel driven four times over add 2190 keyframes in every pass (no reuse); 150 adds
	 * 184 / 28 / 28 after the first pass (doc/generalisation.md). */
	size_t max_backlog_keyframes = 150;
	/** Apply a result as soon as it is ready instead of at k + result_delay_keyframes (live
	 * runs: the robot never waits; the map then depends on timing). Not an .ini key of
	 * [LoopCloser]: lrgc-slam --live sets it from [LiveMapping] loop_results_when_ready, the
	 * one key for it (an offline run is deterministic). */
	bool apply_when_ready = false;
	/** Noise floor of loop links (and end-of-run revisit links); keys link_floor_xy_m [m],
	 * link_floor_phi_deg. Looser than local registration's: a loop link joins scans taken
	 * minutes apart (people, doors, chairs moved). */
	TLinkNoise link_noise;

	void loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
							const std::string& s) override;
	void saveToConfigFile(mrpt::config::CConfigFileBase& c,
						  const std::string& s) const override;
};

}  // namespace lrgc
