/* CTaskGroup: independent jobs, each started at once on its own thread (std::async), and one
 * wait for them all. lrgc-slam writes its output files this way: each file is written and
 * fsynced by itself, so on two cores the encoders (deflate, PNG) and the fsync waits of the
 * files overlap instead of adding up.
 *
 * wait() returns only when every job has ended, then rethrows the first failure in the order
 * the jobs were started: a failing job never leaves another still writing behind the caller's
 * back. The destructor also waits (and drops the failures: it runs while unwinding). */
#pragma once

#include <functional>
#include <future>
#include <vector>

namespace lrgc::apps
{
class CTaskGroup
{
public:
	CTaskGroup() = default;
	~CTaskGroup();
	CTaskGroup(const CTaskGroup&) = delete;
	CTaskGroup& operator=(const CTaskGroup&) = delete;

	/** Starts `job` on a thread of its own. */
	void run(std::function<void()> job);
	/** Waits for every job started; rethrows the first one's exception, if any failed. */
	void wait();

private:
	std::vector<std::future<void>> m_jobs;
};

}  // namespace lrgc::apps
