/* A scan match's covariance computed after the match (issue 32): CScanMatcher::match with a
 * shared reference cloud leaves it to a CDeferredCovariance, which holds what the covariance
 * is computed from (the matched pairs at the solution, their information analysis, the
 * reference cloud, kept alive by its shared pointer) and computes it once, on whichever thread
 * asks first; a thread asking while another computes waits for it. The same code on the same
 * inputs, so the same bits as a covariance computed within the match, whatever the threads'
 * timing: results never depend on who computed it or when.
 *
 * Why (stop 45's profile, range_030_bearing_015): the covariance was 4.8 G of the mapping
 * thread's 19.9 G instructions, while that thread needs it for one decision per scan, and
 * mostly not even there (CLocalRegistration::registerScan); elsewhere it is a value stored
 * with the scan or a link, which the window's helper thread can compute meanwhile.
 */
#pragma once

#include <Eigen/Core>
#include <atomic>
#include <condition_variable>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>

namespace lrgc
{
class CDeferredCovariance
{
public:
	/** `compute` gives the covariance; it is called at most once, then released (with what
	 * it holds: the reference cloud, the pairs). */
	explicit CDeferredCovariance(std::function<Eigen::Matrix3d()> compute);
	CDeferredCovariance(const CDeferredCovariance&) = delete;
	CDeferredCovariance& operator=(const CDeferredCovariance&) = delete;

	/** Computes it on this thread unless a thread has begun to (then returns at once). */
	void compute();
	/** The covariance: computed on this thread unless another has begun, then waited for.
	 * Rethrows what the computation threw. */
	const Eigen::Matrix3d& get();
	/** A thread has begun to compute it (it may not be done). */
	bool claimed() const { return m_claimed.load(); }

private:
	std::atomic<bool> m_claimed{false};
	std::function<Eigen::Matrix3d()> m_compute;
	std::mutex m_mutex;  //!< guards m_done
	std::condition_variable m_cv;
	bool m_done = false;
	Eigen::Matrix3d m_value = Eigen::Matrix3d::Zero();
	std::exception_ptr m_error;
};

/** A covariance that is known, or deferred (shared with the match it came from and its other
 * copies): get() gives it, computing or waiting for a deferred one. */
class CLazyCovariance
{
public:
	/** A known covariance. */
	CLazyCovariance(const Eigen::Matrix3d& known = Eigen::Matrix3d::Identity()) : m_known(known)
	{
	}
	explicit CLazyCovariance(std::shared_ptr<CDeferredCovariance> deferred)
		: m_deferred(std::move(deferred))
	{
	}
	const Eigen::Matrix3d& get() const { return m_deferred ? m_deferred->get() : m_known; }
	/** The deferred computation, null if known. */
	const std::shared_ptr<CDeferredCovariance>& deferred() const { return m_deferred; }
	/** fn(this covariance): at once if it is known, else deferred too (fn runs on the thread
	 * that asks for the result, after this one is computed). */
	CLazyCovariance then(std::function<Eigen::Matrix3d(const Eigen::Matrix3d&)> fn) const;
	/** Known from now on: a deferred one computed (or waited for) and its state released. */
	void settle()
	{
		if (!m_deferred) return;
		m_known = m_deferred->get();
		m_deferred.reset();
	}

private:
	Eigen::Matrix3d m_known;
	std::shared_ptr<CDeferredCovariance> m_deferred;
};

}  // namespace lrgc
