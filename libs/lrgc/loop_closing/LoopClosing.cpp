/* CLoopClosing: the mapping thread's half of the loop-closing protocol (see LoopClosing.h). */
#include <lrgc/loop_closing/LoopClosing.h>

#include <lrgc/loop_closing/LoopClosingWorker.h>
#include <lrgc/loop_closing/LoopCorrection.h>

#include <algorithm>
#include <utility>

namespace lrgc
{
using mrpt::math::TPose2D;

CLoopClosing::CLoopClosing(const TLoopCloserParams& p, const TPatchCorrelatorParams& correlator,
						   const TScanMatcherParams& matcher,
						   const TPoseGraphOptimizerParams& optimizer)
	: m_whenReady(p.apply_when_ready),
	  m_resultDelay(p.result_delay_keyframes),
	  m_worker(std::make_unique<CLoopClosingWorker>(p, correlator, matcher, optimizer))
{
}

CLoopClosing::~CLoopClosing() = default;

TLoopCloserStats CLoopClosing::stats() const
{
	return m_worker->stats();
}

TLoopUpdate CLoopClosing::afterKeyframe(CPoseGraph& graph, const TKeyframes& keyframes,
										bool newKeyframe, size_t anchor, TPose2D& robotInMap,
										double span)
{
	++m_keyframeClock;
	m_grantMs += m_worker->keyframeGrantMs(span);
	TLoopUpdate update;
	applyDue(graph, true, anchor, robotInMap, update);
	if (!newKeyframe || graph.numNodes() < 2) return update;
	handOver(graph, keyframes);
	// Without a delay the search's result is applied at its own keyframe.
	if (m_resultDelay == 0 && !m_whenReady)
		apply(m_worker->take(), graph, anchor, robotInMap, update);
	return update;
}

TLoopUpdate CLoopClosing::whenReady(CPoseGraph& graph, size_t anchor, TPose2D& robotInMap)
{
	TLoopUpdate update;
	applyDue(graph, false, anchor, robotInMap, update);
	return update;
}

void CLoopClosing::searchDeferred(CPoseGraph& graph, const TKeyframes& keyframes)
{
	if (m_whenReady || graph.numNodes() < 2 || m_nodesSent != graph.numNodes()) return;
	handOver(graph, keyframes, true);
}

TLoopUpdate CLoopClosing::drain(CPoseGraph& graph, size_t anchor, TPose2D& robotInMap)
{
	TLoopUpdate update;
	while (m_worker->pending() > 0) apply(m_worker->take(), graph, anchor, robotInMap, update);
	return update;
}

// The results that are due, in job order: a search handed over at keyframe clock c is due
// where the worker's schedule puts it (CLoopClosingWorker::due: c + result_delay_keyframes, or
// where the modelled worker finishes it; waited for if not done), or in a live run once ready.
void CLoopClosing::applyDue(CPoseGraph& graph, bool atKeyframe, size_t anchor,
							TPose2D& robotInMap, TLoopUpdate& update)
{
	while (m_worker->pending() > 0)
	{
		double waited = 0;
		const bool due = m_whenReady
							 ? m_worker->ready()
							 : atKeyframe && m_worker->due(m_keyframeClock, m_grantMs, waited);
		if (waited > 0)
		{
			++m_schedule.waits;
			m_schedule.waitSeconds += waited;
			m_schedule.waitMaxSeconds = std::max(m_schedule.waitMaxSeconds, waited);
		}
		if (!due) break;
		TLoopJobResult r = m_worker->take();
		m_schedule.delayMax = std::max(m_schedule.delayMax, m_keyframeClock - r.clock);
		apply(std::move(r), graph, anchor, robotInMap, update);
	}
}

// A job for the newest keyframe with what the worker's replica lacks (LoopClosing.h); at the
// run's end (searchDeferred) one with no new keyframe.
void CLoopClosing::handOver(CPoseGraph& graph, const TKeyframes& keyframes, bool runsEnd)
{
	const size_t newest = graph.numNodes() - 1;
	TLoopJob job;
	job.newest = newest;
	job.clock = m_keyframeClock;
	job.grantMs = m_grantMs;
	job.firstPose = std::min(graph.takeLowestMovedNode(), m_nodesSent);
	job.poses.assign(graph.poses().begin() + job.firstPose, graph.poses().end());
	for (size_t i = m_nodesSent; i <= newest; ++i) job.scans.push_back(&keyframes[i].scan);
	m_nodesSent = newest + 1;
	collectNewLinks(graph);
	job.links = std::exchange(m_linksToSend, {});
	job.resultsApplied = m_resultsApplied;
	job.stop = m_stop;
	job.frozenNodes = m_frozen;
	job.runsEnd = runsEnd;
	m_worker->submit(std::move(job));
}

void CLoopClosing::collectNewLinks(const CPoseGraph& graph)
{
	for (size_t id = m_linkWatermark; id < graph.numLinks(); ++id)
		m_linksToSend.push_back(graph.link(id));
	m_linkWatermark = graph.numLinks();
}

// A search's result, computed from the graph as it was at keyframe k = r.newest: its links are
// added; if it moved the map, nodes firstMoved..k take its poses and the nodes added since,
// and the robot, are carried along by node k's correction (LoopCorrection.h).
void CLoopClosing::apply(TLoopJobResult&& r, CPoseGraph& graph, size_t anchor,
						 TPose2D& robotInMap, TLoopUpdate& update)
{
	const size_t k = r.newest, n = graph.numNodes();
	if (!r.poses.empty())
	{
		const TPose2D oldK = graph.pose(k), oldAnchor = graph.pose(anchor);
		for (size_t i = 0; i < r.poses.size(); ++i) graph.setPose(r.firstMoved + i, r.poses[i]);
		const TPose2D newK = graph.pose(k);
		for (size_t i = k + 1; i < n; ++i)
			graph.setPose(i, carriedAlong(oldK, newK, graph.pose(i)));
		robotInMap = carriedAlong(oldAnchor, graph.pose(anchor), robotInMap);
		update.posesMoved = true;
	}
	// Links added here since the job go to the worker with the next one, before these.
	collectNewLinks(graph);
	for (size_t i = 0; i < r.links.size(); ++i)
		if (const size_t id = graph.addLink(r.links[i]); !r.linkEnabled[i])
			graph.setLinkEnabled(id, false);
		else if (r.links[i].type == LinkType::LoopClosure)
			update.loopLinked = true;
	m_linkWatermark = graph.numLinks();
	++m_resultsApplied;
	if (!r.closure) return;
	update.loopLinks += 1 + r.closure->rematchLinks;
	update.closures.push_back(*r.closure);
}

}  // namespace lrgc
