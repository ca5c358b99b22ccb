/* CLoopCloser: LRGC's loop closing (Gutmann & Konolige, sections 2.2 use 2, 2.3 and 2.4).
 *
 * After each new keyframe n:
 *  1. Gate. The uncertainty of every old pose relative to n comes from the graph
 *     (propagateUncertainty; reused, chained through its source, for the next
 *     gate_reuse_keyframes keyframes while the old map is unchanged). Old poses (all but the
 * newest m keyframes, m > K) whose position could lie within `overlap_radius_m` of n's, at
 * Mahalanobis distance <= gate_sigma, are candidates. Their largest position std sigma sets the
 * search window
 *     (+- window_sigmas * sigma) and the patch size (grows linearly with sigma), so a large
 *     loop is closed only on strong evidence; both shrink back once a loop is closed.
 *  2. Correlate. The patch (newest P keyframes' scans, in n's frame) is correlated against the
 *     old map built from the candidates' scans (CPatchCorrelator: branch and bound over
 *     (x, y, theta)); the match must pass the score, ambiguity and variance filters.
 *  3. Link. The correlation's pose seeds a scan match of n against the old scans around the
 *     nearest candidate j; the result becomes a LoopClosure link j -> n.
 *  4. Close. If the link disagrees with the current estimate, the whole graph is optimised
 *     (sparse, CHOLMOD) with robust loop links (DCS): a false link is down-weighted and the
 *     closure is counted as rejected. Then the newly linked poses are re-matched (each patch
 *     keyframe against its nearest old keyframe) and the graph optimised again, as the paper
 *     does.
 * With a very uncertain gate (std > confirm_above_sigma_m) step 3's link is held until a later
 * match from a disjoint patch agrees with it; then both links are added and step 4 runs.
 *
 * Beyond the window (issue 28; LoopCloser_far.cpp). The window is capped (max_window_xy_m,
 * max_window_phi_deg): a revisit the drift put farther away lies outside it. While the cap
 * binds and the window finds nothing, every far_search_every_keyframes such checks (on a lane
 * of its own, LoopCloser_lane.cpp: it never moves the near searches' schedule) the patch is
 * correlated with the whole old map within window_sigmas sigma (at least far_window_xy_m, at
 * most the old map's extent), every heading, on a coarse grid (far_resolution_m); its
 * far_candidates best distinct poses per ring of far_window_xy_m
 * (CPatchCorrelator::correlatePeaks) are each searched again at full resolution in a small
 * window with the three filters, then scan-matched (steps 2-3 around that pose). A building
 * holds look-alikes of any patch, so those confirmed are only held; once the patch shares no
 * keyframe with them, each is searched for around the pose of n it implies,
 *     X_n' = X_j (+) z_jk (+) (X_k^-1 (+) X_n)   (held link j -> k),
 * and the loop is closed (both links, step 4) when exactly one held place is matched there
 * and agrees; none within kFarConfirmTries checks, or several, and all are dropped.
 */
#pragma once

#include <lrgc/loop_closing/UncertaintyPropagation.h>
#include <lrgc/loop_closing/LoopCloserParams.h>
#include <lrgc/loop_closing/LoopCloserStats.h>
#include <lrgc/loop_closing/LoopClosure.h>
#include <lrgc/scan_matching/Keyframe.h>
#include <lrgc/pose_graph/LinkNoise.h>
#include <lrgc/loop_closing/PatchCorrelator.h>
#include <lrgc/pose_graph/PoseGraph.h>
#include <lrgc/pose_graph/PoseGraphOptimizer.h>
#include <lrgc/scan_matching/ScanMatcher.h>
#include <mrpt/config/CLoadableOptions.h>

#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace lrgc
{
class CReferenceCloud;
class CLoopCloser
{
public:
	/** The loop closer's own section, and those of the three stages it drives (correlator,
	 * matcher, optimizer). Its loop links' noise floor is p.link_noise. */
	CLoopCloser(const TLoopCloserParams& p, const TPatchCorrelatorParams& correlator,
				const TScanMatcherParams& matcher, const TPoseGraphOptimizerParams& optimizer);
	/** Waits for a far step still running on its thread. */
	~CLoopCloser();
	CLoopCloser(const CLoopCloser&) = delete;
	CLoopCloser& operator=(const CLoopCloser&) = delete;

	/** Looks for a loop for the newest keyframe and closes it; `scans[i]` is node i's scan.
	 * Returns the closure if a link was added (the graph may have been optimised: callers
	 * refresh cached poses). */
	std::optional<TLoopClosure> process(CPoseGraph& graph, const TScanRefs& scans);

	const TLoopCloserStats& stats() const { return m_stats; }
	/** How many of the newest nodes lie within `travel` [m] of path back from the newest one
	 * (path: the straight steps between consecutive nodes, map frame); at least 1. Caps the
	 * patch ([LoopCloser] patch_max_travel_m). */
	static size_t keyframesWithinTravel(const CPoseGraph& graph, double travel);
	/** The near search's patch size [keyframes] (paper 2.4): patch_min_keyframes, plus
	 * patch_keyframes_per_m per metre of the gate's position std `sigmaXY`, plus
	 * `ambiguityGrowth`; at most old_map_exclusion_keyframes (before patch_max_travel_m). */
	static size_t patchKeyframes(const TLoopCloserParams& p, double sigmaXY,
								 size_t ambiguityGrowth);
	/** The patch's growth for ambiguity after a correlation's `verdict`: up by
	 * patch_keyframes_per_ambiguity (at most old_map_exclusion_keyframes) when a near search
	 * was rejected as ambiguous, else as it was. A closure resets it to 0. */
	static size_t grownAfter(const TLoopCloserParams& p, size_t growth,
							 const TCorrelationVerdict& verdict, bool nearSearch);
	/** Whether a near correlation of the sigma's patch (`sigmaPatch` keyframes) rejected with
	 * `verdict` is tried again, in the same check, with the patch grown for ambiguity
	 * (`grownPatch` keyframes): only when it was rejected as ambiguous and the grown patch is
	 * larger (patch_keyframes_per_ambiguity > 0). */
	static bool retriesGrown(const TLoopCloserParams& p, const TCorrelationVerdict& verdict,
							 bool nearSearch, size_t sigmaPatch, size_t grownPatch);
	/** Whether a grown patch of `grownCells` distinct cells adds enough to the sigma's patch
	 * of `sigmaCells` (a subset of them) to be correlated: at least
	 * patch_grown_min_new_cells sigmaCells new cells (fewer: the same correlation again). */
	static bool grownAddsCells(const TLoopCloserParams& p, size_t sigmaCells,
							   size_t grownCells);
	/** The patch's points [newest keyframe's frame]: those of keyframes first..newest within
	 * `maxRange` [m] of the newest keyframe, less an older keyframe's points it saw farther
	 * than `maxRange` away through a gap (a beam within two returned more than `farGap` [m]
	 * nearer; 0: none left out) (LoopCloser_search.cpp); `radius` receives the largest range
	 * from the newest keyframe (0 if none). */
	static std::vector<Eigen::Vector2d> patchPoints(const CPoseGraph& graph,
													const TScanRefs& scans, size_t first,
													double maxRange, double farGap,
													double& radius);
	/** The visit of `nodes` (visitsOf, PoseGraph.h: runs of keyframe indices at most `maxGap`
	 * apart) that holds `node`: the pass through the place (empty if `node` is not among
	 * them). The far check's loop-link reference. */
	static std::vector<size_t> visitAround(std::vector<size_t> nodes, size_t node,
										   size_t maxGap);
	/** The chi2 of a re-match `z` (node j in node i's frame, information `info`) against the
	 * solve's poses xi, xj: the larger of the back end's reading (translation in z's axes) and
	 * the reading in i's axes, where the matcher's covariance is given, with `solveCov` (the
	 * solve's own error between the two) added. rematch() refuses a re-match above 3 Phi. */
	static double rematchDisagreementChi2(const mrpt::math::TPose2D& xi,
										  const mrpt::math::TPose2D& xj,
										  const mrpt::math::TPose2D& z,
										  const Eigen::Matrix3d& info,
										  const Eigen::Matrix3d& solveCov);
	/** The references step 3's loop-link match tries, in order, as keyframe lists: the
	 * keyframes `near` the place (oldNodesNear) and, if they hold several passes, the pass
	 * through `oldNode` alone (visitAround with `maxGap`), tried when the first is refused;
	 * with `oneVisit` (the far check) only that pass. */
	static std::vector<std::vector<size_t>> loopMatchReferences(std::vector<size_t> near,
																size_t oldNode, bool oneVisit,
																size_t maxGap);
	/** Counts a search for `keyframe` deferred by the caller (CLoopClosingWorker's
	 * backlog). */
	void countShed(size_t keyframe)
	{
		++m_stats.searchesShed;
		m_stats.shedKeyframes.push_back(keyframe);
	}
	/** Counts a deferred search merged into a later one whose patch holds its keyframe. */
	void countMerged() { ++m_stats.searchesMerged; }
	/** Counts a deferred search no later search covered: its keyframe and pose [map frame]. */
	void countDropped(size_t keyframe, const mrpt::math::TPose2D& pose)
	{
		m_stats.droppedKeyframes.push_back(keyframe);
		m_stats.droppedPoses.push_back(pose);
	}
	/** At the start of a job of the caller's modelled worker (CLoopClosingWorker): its grant
	 * when the job was handed over [ms of grant, see LoopClosingWorker.h] and the work it
	 * does per keyframe [ms of the reference machine; 0: no modelled worker]. The far search
	 * runs on a lane of its own, a second modelled worker with the same grant: it starts a
	 * step only when that lane is free at the job's grant, and its work is counted apart
	 * (stats().farWork), so the near searches' schedule is the same with it or without. */
	void setSchedule(double grantMs, double budgetMs)
	{
		m_grantMs = grantMs;
		m_budgetMs = budgetMs;
	}
	/** The far lane's step due after the last process(): the next step of the far search
	 * (its start and search for places, or a check of one place). It runs on a loop closer of
	 * its own (its correlators, matcher and counters) over a copy of the graph, on a thread
	 * of its own if setFarThread(true), else now; the caller runs it once the
	 * job's result is handed over. Its outcome (the search's state, the places it holds, its
	 * counters) is taken back only where this loop closer next needs it: at a capped check
	 * where the lane is free at the job's grant by its modelled work, or at a closure. So the
	 * outcome, and what follows from it, does not depend on when the thread runs. */
	void farStep(const CPoseGraph& graph, const TScanRefs& scans);
	/** Whether farStep() runs on a thread of its own (the worker's `background`), and whether
	 * that thread yields the cores to the others (a live run, `apply_when_ready`: the mapping
	 * thread never waits for the loop closer). Offline, a thread at low priority on a loaded
	 * machine fell far behind its modelled lane and the worker waited for it (Killian: latency
	 * max 1035 ms). */
	void setFarThread(bool on, bool yield)
	{
		m_farThreaded = on;
		m_farYields = yield;
	}
	/** Takes back the far step under way, waiting for it (the run's end: its counters). */
	void collectFarStep();
	/** Adds the caller's own work (CLoopClosingWorker's updates of its graph) to stats(). */
	void countWork(const TLoopWork& w) { m_stats.work += w; }
	/** Called after each step of process() (gate, correlation, match, each solve), with
	 * stats().work updated: the worker publishes how far its job has got. */
	void setProgressCallback(std::function<void()> f) { m_onProgress = std::move(f); }
	/** Once `stop` is stopped, process() ends at its next step, its correlation or its
	 * solve (which then leaves the poses as they were) and finds no closure: a loop link it
	 * added is disabled again (lastRejection() says "stopped"). */
	void setStopToken(const CStopToken& stop);
	/** Nodes below `n` are held fixed by every solve (a saved map continued frozen). */
	void setFrozenNodes(size_t n) { m_frozen = n; }
	/** Why the last attempt was rejected (empty if accepted or not attempted). */
	const std::string& lastRejection() const { return m_lastRejection; }

private:
	/** Step 1's result: the old nodes that could overlap the newest. */
	struct TCandidates
	{
		std::vector<size_t> nodes;                   //!< gated old nodes
		std::vector<TRelativeUncertainty> relative;  //!< per node: (newest <- node), covariance
		double sigmaXY = 0, sigmaTheta = 0;  //!< largest position / heading std among them
		/** (newest <- node) of every old node, gated or not (the far search's map). */
		std::vector<TRelativeUncertainty> allOld;
	};
	/** Step 2's search: half window [m, rad] and the patch (keyframes patchFirst..newest). */
	struct TSearchWindow
	{
		double xy = 0, theta = 0;
		size_t patchSize = 0, patchFirst = 0;
		size_t grownByAmbiguity = 0;  //!< of patchSize - patch_min, asked for by ambiguity
		/** Where the window is centred (map <- newest) if not at the newest pose. */
		std::optional<mrpt::math::TPose2D> centre;
		bool far = false;    //!< the far search's coarse grid (m_farCorrelator)
		bool check = false;  //!< the check around a far place (m_farCheckCorrelator)
	};
	struct TPatchAndMap
	{
		std::vector<Eigen::Vector2d> patch;   //!< [newest keyframe's frame]
		std::vector<Eigen::Vector2d> oldMap;  //!< [map frame]
	};
	/** Step 3's loop link (old -> newest) with its information, vetted by the gate. */
	struct TLoopMatch
	{
		TLink link;
		Eigen::Matrix3d info;
		bool vetted = false;
		double score = 0, ambiguity = 0;  //!< of the correlation that seeded it
		/** The correlation's doubt a ridge leaves (carryRidge) [map frame; m^2, rad^2]: the
		 * re-matches after the closure, seeded by it, carry it too. Zero without a ridge. */
		Eigen::Matrix3d doubt = Eigen::Matrix3d::Zero();
	};

	// The steps of process(), in order.
	bool checkDue();
	std::optional<TCandidates> timedGate(const CPoseGraph& graph, size_t newest);
	TSearchWindow searchWindow(const CPoseGraph& graph, const TCandidates& c,
							   size_t ambiguityGrowth, bool capTravel) const;
	bool attemptDue(const TSearchWindow& w);
	std::optional<TLoopClosure> searchNear(CPoseGraph& graph, const TScanRefs& scans,
										   const TCandidates& c, TSearchWindow& w);
	std::optional<TLoopMatch> correlateAndMatch(const CPoseGraph& graph, const TScanRefs& scans,
												const TCandidates& c, TSearchWindow& w);
	std::optional<TCorrelationResult> correlatePatch(const CPoseGraph& graph,
													 const TScanRefs& scans,
													 const TCandidates& c, TSearchWindow& w);
	/** correlatePatch's search with the patch and old map `pm` of `w` built. */
	std::optional<TCorrelationResult> correlatePrepared(const CPoseGraph& graph,
														const TScanRefs& scans,
														const TSearchWindow& w,
														const TPatchAndMap& pm);
	std::optional<TCorrelationResult> correlateGrownOnAmbiguity(const CPoseGraph& graph,
																const TScanRefs& scans,
																const TCandidates& c,
																TSearchWindow& w);
	TPatchAndMap patchAndOldMap(const CPoseGraph& graph, const TScanRefs& scans,
								const TCandidates& c, TSearchWindow& w) const;
	/** Runs `search` with its work counted as it goes (the worker's published progress). */
	void countedSearch(const std::function<void(TCorrelationEffort&)>& search);
	/** Step 3's seed: the correlation's pose, moved along a ridge to the gate's prediction. */
	mrpt::math::TPose2D seedOnRidge(const TCorrelationResult& corr, const TSearchWindow& w,
									const CPoseGraph& graph) const;
	/** A ridge's doubt added to the loop link's covariance (and the link vetted again). */
	void carryRidge(const CPoseGraph& graph, const TCandidates& c,
					const TCorrelationResult& corr, TLoopMatch& m) const;
	std::optional<TLoopMatch> matchLoopLink(const CPoseGraph& graph, const TScanRefs& scans,
											const TCandidates& c,
											const mrpt::math::TPose2D& corrected,
											bool oneVisit);
	std::vector<size_t> oldNodesNear(const CPoseGraph& graph, const TCandidates& c,
									 const mrpt::math::TPose2D& corrected) const;
	CReferenceCloud oldScansNear(const CPoseGraph& graph, const TScanRefs& scans,
								 size_t oldNode, const std::vector<size_t>& near,
								 const mrpt::math::TPose2D& corrected);
	/** Whether a held loop link a and a later one b imply the same pose of b's new node. */
	static bool matchesAgree(const CPoseGraph& g, const TLink& a, const TLink& b);
	/** True (and the rejection named) once a stop is requested. */
	bool stopped();
	bool confirmed(CPoseGraph& graph, const TCandidates& c, const TSearchWindow& w,
				   const TLoopMatch& m, std::optional<size_t>& heldId,
				   std::vector<size_t>& vettedLinks);
	std::optional<TLoopClosure> closeLoop(CPoseGraph& graph, const TScanRefs& scans,
										  const TCandidates& c, const TSearchWindow& w,
										  const TLoopMatch& m);
	/** Step 4 once the match is confirmed: `heldId`, if set, is a confirming link added. */
	std::optional<TLoopClosure> addAndClose(CPoseGraph& graph, const TScanRefs& scans,
											const TCandidates& c, const TSearchWindow& w,
											const TLoopMatch& m, std::optional<size_t> heldId,
											std::vector<size_t>& vettedLinks);

	// Beyond the capped window (LoopCloser_far.cpp).
	static TPatchCorrelatorParams farCorrelatorParams(const TPatchCorrelatorParams& near,
													  const TLoopCloserParams& p);
	static TPatchCorrelatorParams farCheckParams(const TPatchCorrelatorParams& near);
	bool windowCapped(const TCandidates& c) const;
	/** Whether the far lane is free at this job's grant (always without a modelled worker);
	 * takes back the step under way when it has finished by then (LoopCloser_lane.cpp). */
	bool farLaneFree();
	void runFarStep(const CPoseGraph& graph, const TScanRefs& scans, const TCandidates& all,
					const TSearchWindow& w);
	/** Adds the far step's counters (the lane's loop closer's) to stats(). */
	void addFarCounts(const TLoopCloserStats& s);
	/** Runs `work` on the far lane: its modelled work into stats().farWork, its CPU time into
	 * stats().farCpuSeconds, and the lane busy for that work from this job's grant on. */
	void onFarLane(const std::function<void()>& work);
	/** Where the far work is counted: the far lane's, or the near worker's. */
	TLoopWork& work() { return m_onFarLane ? m_stats.farWork : m_stats.work; }
	std::optional<TLoopClosure> searchBeyond(CPoseGraph& graph, const TScanRefs& scans,
											 const TCandidates& c, const TSearchWindow& w);
	void startFarSearch(const CPoseGraph& graph, const TScanRefs& scans, const TCandidates& all,
						TSearchWindow w);
	void farSearchPeaks();
	void checkFarPlace(const CPoseGraph& graph, const TScanRefs& scans, const TCandidates& all,
					   const TSearchWindow& w);
	std::optional<TLoopMatch> matchAround(const CPoseGraph& graph, const TScanRefs& scans,
										  const TCandidates& all, const TSearchWindow& w,
										  const mrpt::math::TPose2D& centre);
	std::optional<TLoopClosure> confirmFar(CPoseGraph& graph, const TScanRefs& scans,
										   const TCandidates& all, const TSearchWindow& w);
	/** Whether a held far place can be confirmed by a patch within `w`'s (farHeldBefore). */
	bool farHeldReady(const TSearchWindow& w) const;
	/** Ends the far search under way for a later one (merged when the later window, of
	 * half-side `laterHalfXY` [m] around the newest keyframe, holds every place it has not
	 * checked; else dropped, its keyframe and pose reported). */
	void supersedeFar(const CPoseGraph& graph, double laterHalfXY);
	void dropFarHeld(size_t& counter);
	double farHalfWindow(const TCandidates& c) const;
	const CPatchCorrelator& correlatorFor(const TSearchWindow& w) const
	{
		return w.far ? m_farCorrelator : w.check ? m_farCheckCorrelator : m_correlator;
	}

	std::optional<TCandidates> gate(const CPoseGraph& graph, size_t newest);
	/** The gate's step model from [LoopCloser] gate_fuse_links, gate_drift_xy_m2_per_m. */
	TStepModel stepModel() const;
	/** (newest <- node) with covariance for every node (gate_reuse_keyframes). */
	std::vector<TRelativeUncertainty> relativeUncertainty(const CPoseGraph& graph,
														  size_t newest);
	std::optional<std::vector<TRelativeUncertainty>> reuseGate(const CPoseGraph& graph,
															   size_t newest) const;
	size_t rematch(CPoseGraph& graph, const TScanRefs& scans, const TCandidates& c,
				   size_t patchFirst, size_t newest, const Eigen::Matrix3d& doubt);

	TLoopCloserParams m_params;
	TScanMatcherParams m_matcherParams;
	CPatchCorrelator m_correlator;
	CPatchCorrelator m_farCorrelator;  //!< the far search's: coarse, clusters of its window
	CPatchCorrelator m_farCheckCorrelator;  //!< the check around a far place's
	CScanMatcher m_matcher;
	CPoseGraphOptimizer m_optimizer;
	size_t m_frozen = 0;  //!< setFrozenNodes()
	TLoopCloserStats m_stats;
	std::function<void()> m_onProgress;
	CStopToken m_stop;
	std::string m_lastRejection;
	/** A whole-graph solve, its effort counted in stats().work; one a stop cut short leaves
	 * the poses as they were (report.stopped). */
	TOptimizationReport optimize(CPoseGraph& graph, const std::vector<size_t>& vetted = {});
	void progress() const
	{
		if (m_onProgress) m_onProgress();
	}
	/** A match held for confirmation (confirm_above_sigma_m): its link and whether the gate
	 * vetted it. */
	struct THeldMatch
	{
		TLink link;
		bool vetted = false;
	};
	std::optional<THeldMatch> m_held;
	/** The last whole-graph propagation: from `anchor`, with the graph's links and the poses
	 * of nodes 0..anchor it saw (to tell whether it still holds). */
	struct TGateCache
	{
		size_t anchor = 0, links = 0;
		std::vector<mrpt::math::TPose2D> poses;
		std::vector<TRelativeUncertainty> labels;  //!< (anchor <- node)
	};
	std::optional<TGateCache> m_gateCache;
	size_t m_keyframesSinceCheck = 0;
	bool m_onKnownGround = false;     //!< the last check added a link that agreed with the map
	size_t m_checksSinceAttempt = 0;  //!< for attempt_stride
	/** Keyframes the grown near patch adds to the sigma's: patch_keyframes_per_ambiguity per
	 * check whose sigma patch was rejected as ambiguous since the last closure. */
	size_t m_ambiguityGrowth = 0;
	/** The filters' verdict on the last correlation (correlatePatch; Accepted when none ran).
	 */
	TCorrelationVerdict m_lastVerdict;
	size_t m_lastPatchCells = 0;  //!< distinct cells of the last correlation's patch
	/** The far search under way (its steps, LoopCloser_far.cpp): the patch of keyframe `newest`
	 * (its frame), the coarse old-map grid and where the patch may stand, then the places to
	 * check. */
	struct TFarSearch
	{
		size_t newest = 0;
		mrpt::math::TPose2D newestInMap;
		double halfXY = 0;
		std::vector<Eigen::Vector2d> patch;
		TOriginRegion origins;  //!< the old keyframes' positions: where the patch may stand
		CCorrelationGrid grid;
		size_t rings = 1;     //!< rings of far_window_xy_m in the window (farSearchPeaks)
		size_t nextRing = 0;  //!< rings searched so far
		/** (map <- patch) to check with their coarse scores; once every ring is searched,
		 * best first over all rings (coarse to fine). */
		std::vector<TCorrelationPeak> places;
		size_t nextPlace = 0;
		bool ringsDone() const { return nextRing >= rings; }
	};
	std::optional<TFarSearch> m_far;
	/** A place the far search proposed and confirmed, held for a later, disjoint patch's
	 * check, and the checks by such patches it has failed so far. */
	struct TFarHeld
	{
		TLoopMatch match;
		size_t tries = 0;
	};
	std::vector<TFarHeld> m_farHeld;
	/** Whether at least patch_min_keyframes of `w`'s patch come after `h`'s newest keyframe:
	 * a patch of its own to confirm `h` (confirmingWindow). */
	bool farHeldBefore(const TFarHeld& h, const TSearchWindow& w) const;
	/** `w` with its patch cut to the keyframes after `h`'s newest: shares none with `h`'s. */
	static TSearchWindow confirmingWindow(const TFarHeld& h, const TSearchWindow& w);
	void dropFarHeldIf(const std::function<bool(const TFarHeld&)>& drop, size_t& counter);
	size_t m_checksSinceFar = 0;  //!< capped checks since the last far search started
	/** The last process()'s capped check that found nothing, for farStep(): every old node
	 * as candidate, and its window. */
	std::optional<std::pair<TCandidates, TSearchWindow>> m_farDue;
	double m_grantMs = 0, m_budgetMs = 0;  //!< setSchedule()
	double m_farFreeMs = 0;                //!< grant at which the far lane is free [ms]
	bool m_onFarLane = false;              //!< work() counts the far lane's
	bool m_farThreaded = false, m_farYields = false;  //!< setFarThread()
	/** The far lane's loop closer and its step under way (LoopCloser_lane.cpp). */
	struct TFarLane;
	std::unique_ptr<TFarLane> m_farLane;
	bool m_farRunning = false;  //!< a step started and not taken back
};

}  // namespace lrgc
