/* CSharedLoop: fn(i) for every i in [0, n), the iterations taken one at a time, in index
 * order, by whichever threads call work(): the thread that owns the loop and any thread that
 * joins it while iterations are left (a thread that would otherwise wait for the loop's
 * result). An iteration runs exactly once; what it computes must not depend on the thread,
 * so the result is the same for any number of helpers and any timing.
 *
 * fn and what it refers to must outlive every work() call that may still take an iteration:
 * the owner calls work() then wait(); a thread that joins late finds nothing left and never
 * calls fn.
 */
#pragma once

#include <lrgc/common/HelperThread.h>

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <vector>

namespace lrgc
{
class CSharedLoop
{
public:
	CSharedLoop(size_t n, const std::function<void(size_t)>& fn)
		: m_fn(&fn), m_n(n), m_errors(n)
	{
	}
	CSharedLoop(const CSharedLoop&) = delete;
	CSharedLoop& operator=(const CSharedLoop&) = delete;

	/** Runs iterations nobody took yet, until none is left to take (an error of fn is kept
	 * for wait()). */
	void work();
	/** Blocks until every iteration has finished; rethrows the error of the lowest index. */
	void wait();
	/** No iteration is left to take (some may still be running). */
	bool exhausted() const { return m_next.load() >= m_n; }

private:
	const std::function<void(size_t)>* m_fn;
	const size_t m_n;
	std::vector<std::exception_ptr> m_errors;  //!< per iteration, written by its thread
	std::atomic<size_t> m_next{0};
	std::mutex m_mutex;  //!< guards m_done
	std::condition_variable m_cv;
	size_t m_done = 0;
};

/** fn(i) for every i in [0, n), shared between the calling thread and `helper` (a
 * CSharedLoop the helper joins when it gets to it); returns once every iteration finished,
 * rethrowing the error of the lowest one. */
void runShared(CHelperThread& helper, size_t n, const std::function<void(size_t)>& fn);

}  // namespace lrgc
