/* CLoopCloser's far lane (issue 28; see LoopCloser.h): the far search runs beside the near
 * searches, never in their schedule, so that on a log where it closes nothing the map is
 * byte for byte the map without it.
 *
 * Model. The lane is a second modelled worker with the near worker's grant G
 * (LoopClosingWorker.h). A step starts at job j only when the lane is free, free_f <= G_j, and
 * then keeps it busy for its modelled work W_f (LoopWork.h), done at half the near worker's
 * speed (kFarLaneSpeed: the lane's thread shares the cores with the mapping thread, the
 * window's helper and the near worker, and the near worker waits whenever the real step is
 * slower than its model): start_f = max(free_f, G_j),  free_f = start_f + W_f / kFarLaneSpeed
 * [ms of grant] W_f is counted in stats().farWork, never in stats().work (the near worker's
 * schedule).
 *
 * Threads. A step of the far search (start and search for places, or a check of one place)
 * reads the graph and moves nothing: it runs on a loop closer of its own (its correlators,
 * matcher and counters, no state shared) over a copy of the graph, on a thread of its own (at
 * low priority in a live run). What it changes (the search's state, the places it holds, its
 * counters) is taken back by this loop closer only where it needs them: at a capped check, once
 * the lane is free at that job's grant (the step's published work so far tells when it is not,
 * without waiting), or at a near closure. So the outcome does not depend on when the thread
 * runs; the worker waits only when the real thread is slower than the modelled lane. The check
 * of held places, which may close a loop, runs in process() on the lane's time (onFarLane).
 */
#include <lrgc/loop_closing/LoopCloser.h>

#include <lrgc/common/CpuTime.h>
#include <lrgc/common/HelperThread.h>
#include <lrgc/common/ThreadPriority.h>

#include <algorithm>
#include <condition_variable>
#include <exception>
#include <mutex>

namespace lrgc
{
namespace
{
// The far lane's speed as a fraction of the near worker's (see the model above).
constexpr double kFarLaneSpeed = 0.5;
}  // namespace

struct CLoopCloser::TFarLane
{
	explicit TFarLane(bool threaded) : helper(threaded) {}

	std::unique_ptr<CLoopCloser> closer;  //!< runs the steps; only the far search's state
	std::mutex mutex;                     // guards what follows up to `helper`
	std::condition_variable cv;
	bool done = false;
	double workMs = 0;     //!< the step's modelled work so far [ms]
	double startMs = 0;    //!< start_f [ms of grant]
	double threadCpu = 0;  //!< the step's thread CPU time [s]
	std::exception_ptr error;
	/** Runs the steps (at once without a thread); last, so that it is destroyed first: a
	 * step under way ends before what it uses goes. */
	CHelperThread helper;
};

// Here, where TFarLane is complete (the constructor destroys m_farLane if it throws).
CLoopCloser::CLoopCloser(const TLoopCloserParams& p, const TPatchCorrelatorParams& correlator,
						 const TScanMatcherParams& matcher,
						 const TPoseGraphOptimizerParams& optimizer)
	: m_params(p),
	  m_matcherParams(matcher),
	  m_correlator(correlator),
	  m_farCorrelator(farCorrelatorParams(correlator, p)),
	  m_farCheckCorrelator(farCheckParams(correlator)),
	  m_matcher(matcher),
	  m_optimizer(optimizer)
{
}

CLoopCloser::~CLoopCloser() = default;  // m_farLane's helper waits for a step under way

bool CLoopCloser::farLaneFree()
{
	if (m_farRunning)
	{
		TFarLane& lane = *m_farLane;
		// Free at G_j iff W_f <= kFarLaneSpeed (G_j - start_f): wait until the work so far
		// exceeds that (busy) or the step is done.
		const bool modelled = m_budgetMs > 0;
		const double room = kFarLaneSpeed * (m_grantMs - lane.startMs);
		bool finished = false;
		{
			std::unique_lock<std::mutex> lock(lane.mutex);
			lane.cv.wait(lock, [&] { return lane.done || (modelled && lane.workMs > room); });
			finished = lane.done && !(modelled && lane.workMs > room);
		}
		if (!finished) return false;
		collectFarStep();
	}
	return m_budgetMs <= 0 || m_farFreeMs <= m_grantMs;
}

void CLoopCloser::onFarLane(const std::function<void()>& work)
{
	CCpuTimer farTimer(m_stats.farCpuSeconds);
	const double before = m_stats.farWork.referenceMs();
	m_onFarLane = true;
	try
	{
		work();
	}
	catch (...)
	{
		m_onFarLane = false;
		throw;
	}
	m_onFarLane = false;
	m_farFreeMs = std::max(m_farFreeMs, m_grantMs) +
				  (m_stats.farWork.referenceMs() - before) / kFarLaneSpeed;
}

void CLoopCloser::farStep(const CPoseGraph& graph, const TScanRefs& scans)
{
	if (!m_farDue) return;
	collectFarStep();  // none under way: a step is due only once the lane is free
	if (!m_farLane)
	{
		m_farLane = std::make_unique<TFarLane>(m_farThreaded);
		m_farLane->closer = std::make_unique<CLoopCloser>(
			m_params, m_correlator.params(), m_matcherParams, m_optimizer.params());
	}
	TFarLane& lane = *m_farLane;
	CLoopCloser& far = *lane.closer;
	far.m_far = std::move(m_far);
	m_far.reset();
	far.m_farHeld = m_farHeld;
	far.m_stats = {};
	far.setStopToken(m_stop);
	far.setProgressCallback(
		[&lane, &far]
		{
			std::lock_guard<std::mutex> lock(lane.mutex);
			lane.workMs = far.m_stats.farWork.referenceMs();
			lane.cv.notify_all();
		});
	lane.done = false;
	lane.workMs = 0;
	lane.error = nullptr;
	lane.startMs = std::max(m_farFreeMs, m_grantMs);
	m_farRunning = true;
	auto step = [&lane, &far, threaded = lane.helper.threaded(), yield = m_farYields,
				 graphCopy = graph, scans, due = std::move(*m_farDue)]
	{
		if (yield) lowerCallingThreadPriority();
		const double cpu0 = threadCpuSeconds();
		std::exception_ptr error;
		try
		{
			far.runFarStep(graphCopy, scans, due.first, due.second);
		}
		catch (...)
		{
			error = std::current_exception();
		}
		std::lock_guard<std::mutex> lock(lane.mutex);
		lane.threadCpu = threaded ? threadCpuSeconds() - cpu0 : 0.0;
		lane.workMs = far.m_stats.farWork.referenceMs();
		lane.error = error;
		lane.done = true;
		lane.cv.notify_all();
	};
	m_farDue.reset();
	lane.helper.post(std::move(step));
}

void CLoopCloser::collectFarStep()
{
	if (!m_farRunning) return;
	TFarLane& lane = *m_farLane;
	{
		std::unique_lock<std::mutex> lock(lane.mutex);
		lane.cv.wait(lock, [&] { return lane.done; });
	}
	m_farRunning = false;
	if (lane.error) std::rethrow_exception(lane.error);
	CLoopCloser& far = *lane.closer;
	far.setProgressCallback({});
	m_far = std::move(far.m_far);
	far.m_far.reset();
	m_farHeld = std::move(far.m_farHeld);
	far.m_farHeld.clear();
	if (!m_far && !m_farHeld.empty())
		m_lastRejection = "far matches held until a later patch confirms one";
	addFarCounts(far.m_stats);
	m_stats.farThreadCpuSeconds += lane.threadCpu;
	m_farFreeMs = lane.startMs + far.m_stats.farWork.referenceMs() / kFarLaneSpeed;
}

// The counters a far step touches (runFarStep and what it calls).
void CLoopCloser::addFarCounts(const TLoopCloserStats& s)
{
	m_stats.attempts += s.attempts;
	m_stats.rejectedByFilters += s.rejectedByFilters;
	m_stats.rejectedByMatch += s.rejectedByMatch;
	m_stats.onePassRetries += s.onePassRetries;
	m_stats.onePassMatched += s.onePassMatched;
	m_stats.heldForConfirmation += s.heldForConfirmation;
	m_stats.farSearches += s.farSearches;
	m_stats.farRings += s.farRings;
	m_stats.farCandidates += s.farCandidates;
	m_stats.farConfirmed += s.farConfirmed;
	m_stats.farRejected += s.farRejected;
	m_stats.correlateCpuSeconds += s.correlateCpuSeconds;
	m_stats.matchCpuSeconds += s.matchCpuSeconds;
	m_stats.farCpuSeconds += s.farCpuSeconds;
	m_stats.farWork += s.farWork;
}

}  // namespace lrgc
