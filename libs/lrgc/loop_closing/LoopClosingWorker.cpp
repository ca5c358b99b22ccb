/* CLoopClosingWorker: the replica's bookkeeping and the thread (see LoopClosingWorker.h). */
#include <lrgc/loop_closing/LoopClosingWorker.h>

#include <mrpt/core/exceptions.h>

namespace lrgc
{
CLoopClosingWorker::CLoopClosingWorker(
	const TLoopCloserParams& p, const TPatchCorrelatorParams& correlator,
	const TScanMatcherParams& matcher, const TPoseGraphOptimizerParams& optimizer)
	: m_closer(p, correlator, matcher, optimizer)
{
	if (p.background) m_thread = std::thread([this] { threadMain(); });
}

CLoopClosingWorker::~CLoopClosingWorker()
{
	if (!m_thread.joinable()) return;
	{
		std::lock_guard<std::mutex> lock(m_mutex);
		m_stop = true;
	}
	m_cv.notify_all();
	m_thread.join();
}

void CLoopClosingWorker::submit(TLoopJob job)
{
	ASSERTMSG_(!m_pending, "CLoopClosingWorker::submit: the previous result was not taken");
	m_pending = true;
	m_pendingNode = job.newest;
	if (!m_thread.joinable())
	{
		try
		{
			m_result = execute(job);
		}
		catch (...)
		{
			m_error = std::current_exception();
		}
		return;
	}
	{
		std::lock_guard<std::mutex> lock(m_mutex);
		m_job = std::move(job);
	}
	m_cv.notify_all();
}

bool CLoopClosingWorker::ready() const
{
	std::lock_guard<std::mutex> lock(m_mutex);
	return m_pending && (m_result || m_error);
}

TLoopJobResult CLoopClosingWorker::take()
{
	ASSERTMSG_(m_pending, "CLoopClosingWorker::take: no job was submitted");
	std::unique_lock<std::mutex> lock(m_mutex);
	m_cv.wait(lock, [this] { return m_result || m_error; });
	m_pending = false;
	if (m_error) std::rethrow_exception(std::exchange(m_error, nullptr));
	TLoopJobResult r = std::move(*m_result);
	m_result.reset();
	return r;
}

TLoopCloserStats CLoopClosingWorker::stats() const
{
	std::lock_guard<std::mutex> lock(m_mutex);
	return m_stats;
}

void CLoopClosingWorker::threadMain()
{
	std::unique_lock<std::mutex> lock(m_mutex);
	for (;;)
	{
		m_cv.wait(lock, [this] { return m_stop || m_job; });
		if (!m_job) return;  // stop requested, nothing in hand
		TLoopJob job = std::move(*m_job);
		m_job.reset();
		lock.unlock();
		std::optional<TLoopJobResult> result;
		std::exception_ptr error;
		try
		{
			result = execute(job);
		}
		catch (...)
		{
			error = std::current_exception();
		}
		lock.lock();
		m_result = std::move(result);
		m_error = error;
		m_cv.notify_all();
	}
}

// Brings the replica up to date with the job, runs the loop closer on it, and reports what
// it changed. Runs on the worker thread (or in submit() without one); touches no state of the
// mapping thread but what the job holds (scans are read through stable addresses).
TLoopJobResult CLoopClosingWorker::execute(TLoopJob& job)
{
	if (const int64_t ms = m_extraDelayMs.load(); ms > 0)
		std::this_thread::sleep_for(std::chrono::milliseconds(ms));
	ASSERT_EQUAL_(job.firstPose + job.poses.size(), job.newest + 1);
	ASSERT_(job.firstPose <= m_replica.numNodes());
	ASSERT_EQUAL_(m_scans.size() + job.scans.size(), job.newest + 1);
	for (size_t i = 0; i < job.poses.size(); ++i)
	{
		const size_t node = job.firstPose + i;
		if (node < m_replica.numNodes()) m_replica.setPose(node, job.poses[i]);
		else m_replica.addNode(job.poses[i]);
	}
	m_scans.insert(m_scans.end(), job.scans.begin(), job.scans.end());
	for (const TLink& l : job.links) m_replica.addLink(l);
	m_replica.takeLowestMovedNode();  // from here on, only the loop closer's moves count

	const size_t firstLink = m_replica.numLinks();
	TLoopJobResult r;
	r.newest = job.newest;
	r.closure = m_closer.process(m_replica, m_scans);
	r.rejection = m_closer.lastRejection();
	for (size_t id = firstLink; id < m_replica.numLinks(); ++id)
	{
		r.links.push_back(m_replica.link(id));
		r.linkEnabled.push_back(m_replica.isLinkEnabled(id) ? 1 : 0);
	}
	// A closure refused by the back-end is undone by a second optimisation: the poses moved
	// all the same, so they are reported whenever any moved.
	r.firstMoved = m_replica.takeLowestMovedNode();
	r.poses.assign(m_replica.poses().begin() + r.firstMoved, m_replica.poses().end());
	{
		std::lock_guard<std::mutex> lock(m_mutex);
		m_stats = m_closer.stats();
	}
	return r;
}

}  // namespace lrgc
