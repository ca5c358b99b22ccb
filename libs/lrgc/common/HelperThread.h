/* CHelperThread: one thread that runs its owner's jobs in the order they were posted, so the
 * owner can hand off work whose result it needs later (a cloud for the next scan) or share
 * work it is waiting for (matches it would otherwise run one after the other).
 *
 * A job's result, and whatever it throws, goes into state it shares with its owner (a job
 * that lets an exception out ends the process). The thread starts with the first job, and
 * the destructor lets the queued jobs run to their end (so a job must never wait for its
 * owner). Without a thread (`threaded` false) post() runs the job at once on the caller's
 * thread: the same results, for tests and debugging.
 */
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>

namespace lrgc
{
class CHelperThread
{
public:
	explicit CHelperThread(bool threaded = true) : m_threaded(threaded) {}
	/** Runs the jobs still queued, then stops the thread. */
	~CHelperThread();
	CHelperThread(const CHelperThread&) = delete;
	CHelperThread& operator=(const CHelperThread&) = delete;

	/** Queues `job` (runs it now without a thread). */
	void post(std::function<void()> job);
	bool threaded() const { return m_threaded; }

private:
	void threadMain();

	const bool m_threaded;
	std::mutex m_mutex;  // guards what follows
	std::condition_variable m_cv;
	std::deque<std::function<void()>> m_jobs;
	bool m_stop = false;
	std::thread m_thread;  // started by the first post()
};

}  // namespace lrgc
