/* CTaskGroup: independent jobs run by at most `threads` threads of the group, in the order
 * they were started, and one wait for them all. lrgc-slam writes its output files this way:
 * each file is written and fsynced by itself, so on two cores the encoders (deflate, PNG) and
 * the fsync waits of the files overlap instead of adding up. A few threads, not one per job:
 * each thread that allocates gets its own malloc arena, and the files' buffers (a grid image,
 * its PNG, map.pgm) would all be alive at once.
 *
 * wait() returns only when every job has ended, then rethrows the first failure in the order
 * the jobs were started: a failing job never leaves another still writing behind the caller's
 * back. The destructor also waits (and drops the failures: it runs while unwinding). */
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace lrgc::apps
{
class CTaskGroup
{
public:
	explicit CTaskGroup(size_t threads = 2) : m_maxThreads(threads > 0 ? threads : 1) {}
	~CTaskGroup();
	CTaskGroup(const CTaskGroup&) = delete;
	CTaskGroup& operator=(const CTaskGroup&) = delete;

	/** Queues `job`; a thread of the group takes it as soon as one is free. */
	void run(std::function<void()> job);
	/** Waits for every job started; rethrows the first one's exception, if any failed. */
	void wait();

private:
	void threadMain();
	void joinAll();

	const size_t m_maxThreads;
	std::vector<std::thread> m_threads;                            // the caller's only
	std::mutex m_mutex;                                            // guards what follows
	std::deque<std::pair<size_t, std::function<void()>>> m_queue;  // (job index, job)
	std::vector<std::exception_ptr> m_failures;                    // by job index
	size_t m_busyThreads = 0;  // threads running or about to take a job
};

}  // namespace lrgc::apps
