/* CLiveSaver: the thread that writes a live run's periodic saves, so that the mapping thread
 * never waits for the disk or for the grid.
 *
 * The mapping thread takes a snapshot between two scans (poses, trajectory, graph, counters,
 * and shared pointers to the keyframes' scans, which never change: TRunOutputsSnapshot) and
 * hands the save over as a job; this thread runs it: builds the grid (incrementally, with a
 * CIncrementalGrid of its own) and writes the files, each atomically. One save at a time: while
 * one runs, trySubmit() refuses the next and the mapping thread simply tries again later, so
 * saves never queue up behind a slow disk. The thread runs at a lower priority than the
 * mapping thread (lowerCallingThreadPriority).
 */
#pragma once

#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>

namespace lrgc::apps
{
class CLiveSaver
{
public:
	CLiveSaver();
	/** Waits for the running job, then ends the thread. */
	~CLiveSaver();
	CLiveSaver(const CLiveSaver&) = delete;
	CLiveSaver& operator=(const CLiveSaver&) = delete;

	/** True if no job runs or waits. */
	bool idle() const;
	/** Runs `job` on the saver thread, unless a job runs or waits (then returns false and
	 * drops it). `job` must not throw: it reports its own errors. */
	bool trySubmit(std::function<void()> job);
	/** Returns once no job runs or waits. */
	void waitIdle();

private:
	void threadMain();

	mutable std::mutex m_mutex;
	std::condition_variable m_changed;
	std::function<void()> m_job;  //!< the job waiting or running; empty when idle
	bool m_stop = false;
	std::thread m_thread;  //!< last: started once the rest exists
};

}  // namespace lrgc::apps
