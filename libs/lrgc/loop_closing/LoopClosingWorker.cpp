/* CLoopClosingWorker: the replica's bookkeeping and the thread (see LoopClosingWorker.h). */
#include <lrgc/loop_closing/LoopClosingWorker.h>

#include <lrgc/common/CpuTime.h>
#include <lrgc/loop_closing/LoopCorrection.h>

#include <lrgc/common/ThreadPriority.h>
#include <lrgc/common/se2.h>
#include <mrpt/core/exceptions.h>

#include <algorithm>
#include <cmath>

namespace lrgc
{
using mrpt::math::TPose2D;

namespace
{
/** A keyframe grants the modelled worker at most this many keyframes' worth of
 * worker_budget_ms: a robot that stood still for minutes must not let every queued search fall
 * due at once (the mapping thread would wait for the real worker to do them all). 4: a sparse
 * keyframe spans 3-5 keyframe spacings of travel. */
constexpr double kMaxGrantKeyframes = 4;
}  // namespace

CLoopClosingWorker::CLoopClosingWorker(const TLoopCloserParams& p,
									   const TPatchCorrelatorParams& correlator,
									   const TScanMatcherParams& matcher,
									   const TPoseGraphOptimizerParams& optimizer)
	: m_resultDelay(p.result_delay_keyframes),
	  // Live runs take results when ready: the model would only shed searches the real
	  // worker, given the robot's time, has done long ago.
	  m_budgetMs(p.apply_when_ready ? 0.0 : p.worker_budget_ms),
	  m_budgetSpan(p.worker_budget_span),
	  m_maxBacklogMs(double(p.max_backlog_keyframes) * p.worker_budget_ms),
	  m_searchSpacing(p.patch_min_keyframes),
	  m_closer(p, correlator, matcher, optimizer)
{
	m_closer.setFarThread(p.background, p.apply_when_ready);
	// Results taken whenever ready (a live run): the mapping thread never waits for this
	// thread, so it yields the cores to it.
	if (p.background)
		m_thread = std::thread(
			[this, yield = p.apply_when_ready]
			{
				if (yield) lowerCallingThreadPriority();
				threadMain();
			});
}

CLoopClosingWorker::~CLoopClosingWorker()
{
	if (!m_thread.joinable()) return;
	{
		std::lock_guard<std::mutex> lock(m_mutex);
		m_stop = true;
		m_jobs.clear();  // results nobody will take
	}
	m_cv.notify_all();
	m_thread.join();
}

void CLoopClosingWorker::submit(TLoopJob job)
{
	m_pendingClocks.push_back(job.clock);
	if (!m_thread.joinable())
	{
		if (m_error) return;  // a job failed: take() reports it
		try
		{
			m_results.push_back(execute(job));
			farStep();
		}
		catch (...)
		{
			m_error = std::current_exception();
		}
		return;
	}
	{
		std::lock_guard<std::mutex> lock(m_mutex);
		m_jobs.push_back(std::move(job));
	}
	m_cv.notify_all();
}

bool CLoopClosingWorker::ready() const
{
	std::lock_guard<std::mutex> lock(m_mutex);
	return !m_pendingClocks.empty() && (!m_results.empty() || m_error);
}

bool CLoopClosingWorker::isDue(size_t jobClock, double finishMs, size_t clock,
							   double grantMs) const
{
	return clock >= jobClock + m_resultDelay && (m_budgetMs <= 0 || finishMs <= grantMs);
}

double CLoopClosingWorker::keyframeGrantMs(double span) const
{
	if (m_budgetSpan <= 0) return m_budgetMs;
	return m_budgetMs * std::clamp(span / m_budgetSpan, 1.0, kMaxGrantKeyframes);
}

bool CLoopClosingWorker::due(size_t clock, double grantMs, double& waitedSeconds)
{
	ASSERTMSG_(!m_pendingClocks.empty(), "CLoopClosingWorker::due: no job was submitted");
	const auto t0 = std::chrono::steady_clock::now();
	bool waited = false;
	std::unique_lock<std::mutex> lock(m_mutex);
	for (;;)
	{
		if (m_error) break;
		if (!m_results.empty())
		{
			const TLoopJobResult& r = m_results.front();
			if (!isDue(r.clock, r.finishMs, clock, grantMs)) return false;
			break;
		}
		// Not done: due only if even the least finish its work so far implies is.
		const double leastFinish = m_runningJob == m_taken ? m_runningFinishMs : 0.0;
		if (!isDue(m_pendingClocks.front(), leastFinish, clock, grantMs)) break;
		m_cv.wait(lock);
		waited = true;
	}
	if (waited)
		waitedSeconds +=
			std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
	return m_error || !m_results.empty();
}

TLoopJobResult CLoopClosingWorker::take()
{
	ASSERTMSG_(!m_pendingClocks.empty(), "CLoopClosingWorker::take: no job was submitted");
	std::unique_lock<std::mutex> lock(m_mutex);
	m_cv.wait(lock, [this] { return !m_results.empty() || m_error; });
	m_pendingClocks.pop_front();
	++m_taken;
	if (m_error) std::rethrow_exception(m_error);
	TLoopJobResult r = std::move(m_results.front());
	m_results.pop_front();
	return r;
}

TLoopCloserStats CLoopClosingWorker::stats() const
{
	std::lock_guard<std::mutex> lock(m_mutex);
	TLoopCloserStats s = m_stats;
	s.workerThreadCpuSeconds = m_threadCpuSeconds + s.farThreadCpuSeconds;
	return s;
}

void CLoopClosingWorker::threadMain()
{
	std::unique_lock<std::mutex> lock(m_mutex);
	for (;;)
	{
		m_cv.wait(lock, [this] { return m_stop || !m_jobs.empty(); });
		if (m_jobs.empty() || m_error) return;  // stop requested (or a job failed)
		TLoopJob job = std::move(m_jobs.front());
		m_jobs.pop_front();
		lock.unlock();
		std::optional<TLoopJobResult> result;
		std::exception_ptr error;
		const double cpu0 = threadCpuSeconds();
		try
		{
			result = execute(job);
		}
		catch (...)
		{
			error = std::current_exception();
		}
		lock.lock();
		m_threadCpuSeconds += threadCpuSeconds() - cpu0;
		if (result) m_results.push_back(std::move(*result));
		if (error) m_error = error;
		m_cv.notify_all();
		if (error) continue;
		// The result is handed over: the far lane's step, if one is due, runs now.
		lock.unlock();
		const double farCpu0 = threadCpuSeconds();
		try
		{
			farStep();
		}
		catch (...)
		{
			error = std::current_exception();
		}
		lock.lock();
		m_threadCpuSeconds += threadCpuSeconds() - farCpu0;
		if (error) m_error = error;
		m_cv.notify_all();
	}
}

void CLoopClosingWorker::farStep()
{
	m_closer.farStep(m_replica, m_scans);
	std::lock_guard<std::mutex> lock(m_mutex);
	publishStats();
}

// The job's poses M_i are in the mapping thread's frame, which lacks the corrections it had
// not applied when it sent them. For each node, the latest such correction that concerns it
// decides, as the mapping thread will when it applies them in order:
//  - firstMoved <= i <= k: the result placed node i; the replica keeps it;
//  - i > k: carried along by node k's correction (LoopCorrection.h) from the poses sent,
//    X_i = X'_k (+) (M_k^-1 (+) M_i); the earlier corrections, rigid motions of both M_k and
//    M_i, cancel out in this product;
//  - i < firstMoved: that correction did not touch i; look at the one before.
void CLoopClosingWorker::updateReplica(const TLoopJob& job)
{
	while (!m_unapplied.empty() && m_unapplied.front().sequence < job.resultsApplied)
		m_unapplied.erase(m_unapplied.begin());
	ASSERT_(job.firstPose <= m_sentPoses.size());
	m_sentPoses.resize(job.newest + 1);
	std::copy(job.poses.begin(), job.poses.end(), m_sentPoses.begin() + job.firstPose);
	for (size_t node = job.firstPose; node <= job.newest; ++node)
	{
		std::optional<TPose2D> pose = m_sentPoses[node];
		for (auto c = m_unapplied.rbegin(); c != m_unapplied.rend(); ++c)
		{
			if (node > c->newest)
			{
				pose = carriedAlong(m_sentPoses[c->newest], c->newestPose, m_sentPoses[node]);
				break;
			}
			if (node >= c->firstMoved)
			{
				pose.reset();  // the result's own pose stays
				break;
			}
		}
		if (node >= m_replica.numNodes())
			m_replica.addNode(pose ? *pose : m_sentPoses[node]);
		else if (pose)
			m_replica.setPose(node, *pose);
	}
}

void CLoopClosingWorker::publishProgress(double finishMs)
{
	{
		std::lock_guard<std::mutex> lock(m_mutex);
		m_runningJob = m_jobsDone;
		m_runningFinishMs = finishMs;
	}
	m_cv.notify_all();
}

// The modelled worker's backlog (see the header): past max_backlog_keyframes *
// worker_budget_ms, a job defers its search unless the last one ran patch_min_keyframes
// keyframes ago. A search that runs for node n merges the deferred searches whose keyframe
// lies in its patch (n + 1 - patch_min_keyframes or later: a patch is never shorter) and
// drops the others, recording where they were. The run's last job searches only to merge
// deferred searches.
std::optional<TLoopClosure> CLoopClosingWorker::searchOrDefer(const TLoopJob& job, double start)
{
	if (job.runsEnd && m_deferred.empty()) return std::nullopt;
	if (!job.runsEnd && m_budgetMs > 0 && start - job.grantMs > m_maxBacklogMs &&
		job.newest < m_lastSearched + m_searchSpacing)
	{
		m_closer.countShed(job.newest);
		m_deferred.push_back(job.newest);
		return std::nullopt;
	}
	for (const size_t d : m_deferred)
		if (d + m_searchSpacing > job.newest)
			m_closer.countMerged();
		else
			m_closer.countDropped(d, m_replica.pose(d));
	m_deferred.clear();
	m_lastSearched = job.newest;
	m_closer.setSchedule(job.grantMs, m_budgetMs);
	return m_closer.process(m_replica, m_scans);
}

// Brings the replica up to date with the job, runs the loop closer on it, and reports what
// it changed. Runs on the worker thread (or in submit() without one); touches no state of the
// mapping thread but what the job holds (scans are read through stable addresses).
TLoopJobResult CLoopClosingWorker::execute(TLoopJob& job)
{
	if (const int64_t ms = m_extraDelayMs.load(); ms > 0)
		std::this_thread::sleep_for(std::chrono::milliseconds(ms));
	ASSERT_EQUAL_(job.firstPose + job.poses.size(), job.newest + 1);
	ASSERT_EQUAL_(m_scans.size() + job.scans.size(), job.newest + 1);
	updateReplica(job);
	m_scans.insert(m_scans.end(), job.scans.begin(), job.scans.end());
	for (const TLink& l : job.links) m_replica.addLink(l);
	m_replica.takeLowestMovedNode();  // from here on, only the loop closer's moves count

	// The modelled worker's schedule (see the header); its work: this job's update of the
	// replica and what the loop closer counts.
	const double start = std::max(job.grantMs, m_modelledFree);
	const TLoopWork before = m_closer.stats().work;
	TLoopWork update;
	update.jobs = 1, update.newScans = job.scans.size();
	const auto workSoFar = [&]
	{
		TLoopWork w = m_closer.stats().work - before;
		return w += update;
	};
	publishProgress(start + workSoFar().referenceMs());
	m_closer.setStopToken(job.stop);
	m_closer.setFrozenNodes(job.frozenNodes);
	m_closer.setProgressCallback([&] { publishProgress(start + workSoFar().referenceMs()); });

	const size_t firstLink = m_replica.numLinks();
	TLoopJobResult r;
	r.newest = job.newest;
	r.clock = job.clock;
	r.closure = searchOrDefer(job, start);
	if (job.runsEnd) m_closer.collectFarStep();  // its counters
	m_closer.setProgressCallback({});
	r.finishMs = start + workSoFar().referenceMs();
	m_modelledFree = r.finishMs;
	m_closer.countWork(update);
	for (size_t id = firstLink; id < m_replica.numLinks(); ++id)
	{
		r.links.push_back(m_replica.link(id));
		r.linkEnabled.push_back(m_replica.isLinkEnabled(id) ? 1 : 0);
	}
	// A closure refused by the back-end is undone by a second optimisation: the poses moved
	// all the same, so they are reported whenever any moved.
	r.firstMoved = m_replica.takeLowestMovedNode();
	r.poses.assign(m_replica.poses().begin() + r.firstMoved, m_replica.poses().end());
	if (!r.poses.empty())
		m_unapplied.push_back({m_jobsDone, r.newest, r.firstMoved, m_replica.pose(r.newest)});
	++m_jobsDone;
	std::lock_guard<std::mutex> lock(m_mutex);
	publishStats();
	return r;
}

void CLoopClosingWorker::publishStats()
{
	m_stats = m_closer.stats();
	for (const size_t d : m_deferred)  // not merged yet: dropped unless a search comes
	{
		m_stats.droppedKeyframes.push_back(d);
		m_stats.droppedPoses.push_back(m_replica.pose(d));
	}
}

}  // namespace lrgc
