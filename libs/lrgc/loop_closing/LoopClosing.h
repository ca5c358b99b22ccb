/* CLoopClosing: the loop-closing protocol as the mapping thread sees it (Gutmann & Konolige
 * 2000, section 2.4: loop closing runs "in the background" while the robot keeps mapping).
 *
 * The map builder has one call per keyframe, afterKeyframe(): it applies the loop results that
 * are due, then hands the newest keyframe over to the worker (CLoopClosingWorker, which owns
 * the replica of the graph and the CLoopCloser). Everything the two threads share is here and
 * in LoopClosingWorker.*, each rule written once:
 *  - a job carries what the worker's replica lacks: the nodes added since the last job (poses
 *    and scans), the poses moved (CPoseGraph::takeLowestMovedNode), the links added;
 *  - a result is applied in job order, at the keyframe the worker's schedule fixes
 *    (CLoopClosingWorker::due), or as soon as it is ready in a live run (apply_when_ready);
 *  - a result that moved the map places nodes firstMoved..k, and the nodes added since job k
 *    (and the robot) are carried along by node k's correction (LoopCorrection.h).
 * With loop closing off the object is not made (the builder holds a null pointer).
 */
#pragma once

#include <lrgc/loop_closing/LoopCloserParams.h>
#include <lrgc/common/StopToken.h>
#include <lrgc/loop_closing/LoopCloserStats.h>
#include <lrgc/loop_closing/LoopClosure.h>
#include <lrgc/loop_closing/PatchCorrelatorParams.h>
#include <lrgc/pose_graph/PoseGraph.h>
#include <lrgc/pose_graph/PoseGraphOptimizerParams.h>
#include <lrgc/scan_matching/Keyframe.h>
#include <lrgc/scan_matching/ScanMatcherParams.h>

#include <mrpt/core/Clock.h>

#include <memory>
#include <optional>
#include <vector>

namespace lrgc
{
class CLoopClosingWorker;
struct TLoopJobResult;
struct TLoopClosingTestAccess;

/** What applying the due results did to the mapping thread's graph. */
struct TLoopUpdate
{
	bool posesMoved = false;  //!< some result moved the map: caches of poses are stale
	bool loopLinked = false;  //!< an enabled loop link was added: the robot is tied to the map
	std::vector<TLoopClosure> closures;  //!< accepted closures, in the order applied
	size_t loopLinks = 0;  //!< loop links of those closures (1 + re-matched links each)
};

/** The mapping thread's waits for loop results and how late results landed. */
struct TLoopScheduleStats
{
	/** Times the mapping thread waited for a result (not done by its due keyframe), and the
	 * time waited [s] in all and at most once. */
	size_t waits = 0;
	double waitSeconds = 0, waitMaxSeconds = 0;
	size_t delayMax = 0;  //!< [keyframes] most keyframes between a job and its result's use
};

class CLoopClosing
{
public:
	CLoopClosing(const TLoopCloserParams& p, const TPatchCorrelatorParams& correlator,
				 const TScanMatcherParams& matcher, const TPoseGraphOptimizerParams& optimizer);
	/** Lets the worker's job in hand finish and drops the queued ones. */
	~CLoopClosing();
	CLoopClosing(const CLoopClosing&) = delete;
	CLoopClosing& operator=(const CLoopClosing&) = delete;

	/** At a keyframe taken `span` keyframe spacings of travel after the previous one (the
	 * keyframe clock advances, and the modelled worker's grant with it): applies the results
	 * due by now, then, for a new keyframe (`newKeyframe`; not at a reused one), hands it over
	 * for a loop search. `anchor` is the keyframe the robot hangs from and `robotInMap` its
	 * pose: carried along by the corrections applied. */
	TLoopUpdate afterKeyframe(CPoseGraph& graph, const TKeyframes& keyframes, bool newKeyframe,
							  size_t anchor, mrpt::math::TPose2D& robotInMap, double span);
	/** Between keyframes of a live run (apply_when_ready): applies the results ready now. */
	TLoopUpdate whenReady(CPoseGraph& graph, size_t anchor, mrpt::math::TPose2D& robotInMap);
	/** End of the run, before drain(): hands the newest keyframe over once more, to run the
	 * searches the worker deferred after its last search (no later keyframe will merge them;
	 * CLoopClosingWorker: nothing is searched if none was deferred). */
	void searchDeferred(CPoseGraph& graph, const TKeyframes& keyframes);
	/** End of the run: waits for every search handed over and applies its result. */
	TLoopUpdate drain(CPoseGraph& graph, size_t anchor, mrpt::math::TPose2D& robotInMap);

	/** The searches handed over from now on honour `stop` (CLoopCloser::setStopToken): once
	 * it is stopped, the one in hand ends early and adds nothing, and the later ones add
	 * nothing, so drain() returns promptly. */
	void setStopToken(const CStopToken& stop) { m_stop = stop; }
	/** The searches handed over from now on hold nodes below `n` fixed in their solves. */
	void setFrozenNodes(size_t n) { m_frozen = n; }

	TLoopCloserStats stats() const;  //!< the worker's counters (any thread)
	const TLoopScheduleStats& schedule() const { return m_schedule; }

private:
	friend struct TLoopClosingTestAccess;  // tests: a slow worker (LoopClosingTestAccess.h)

	void applyDue(CPoseGraph& graph, bool atKeyframe, size_t anchor,
				  mrpt::math::TPose2D& robotInMap, TLoopUpdate& update);
	void handOver(CPoseGraph& graph, const TKeyframes& keyframes, bool runsEnd = false);
	void apply(TLoopJobResult&& r, CPoseGraph& graph, size_t anchor,
			   mrpt::math::TPose2D& robotInMap, TLoopUpdate& update);
	/** Queues the links added to `graph` since the last call for the next job. */
	void collectNewLinks(const CPoseGraph& graph);

	const bool m_whenReady;  //!< apply_when_ready
	const size_t m_resultDelay;
	std::unique_ptr<CLoopClosingWorker> m_worker;
	/** What the worker's replica lacks: links not yet sent (those added before the last
	 * applied result, and from id m_linkWatermark on), nodes from m_nodesSent on. */
	std::vector<TLink> m_linksToSend;
	size_t m_linkWatermark = 0;
	size_t m_nodesSent = 0;
	size_t m_resultsApplied = 0;  //!< in job order
	/** Keyframes taken so far, new or reused: the clock of the worker's schedule (a robot
	 * driving known ground reuses keyframes and adds none, but its results must land). */
	size_t m_keyframeClock = 0;
	/** The modelled worker's grant so far [ms] (CLoopClosingWorker::keyframeGrantMs per
	 * keyframe taken). */
	double m_grantMs = 0;
	TLoopScheduleStats m_schedule;
	CStopToken m_stop;
	size_t m_frozen = 0;
};

}  // namespace lrgc
