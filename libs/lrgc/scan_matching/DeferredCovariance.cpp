/* CDeferredCovariance: computed once, by the first thread that asks; see DeferredCovariance.h.
 */
#include <lrgc/scan_matching/DeferredCovariance.h>

#include <utility>

namespace lrgc
{
CDeferredCovariance::CDeferredCovariance(std::function<Eigen::Matrix3d()> compute)
	: m_compute(std::move(compute))
{
}

void CDeferredCovariance::compute()
{
	if (m_claimed.exchange(true)) return;
	Eigen::Matrix3d value = Eigen::Matrix3d::Zero();
	std::exception_ptr error;
	try
	{
		value = m_compute();
	}
	catch (...)
	{
		error = std::current_exception();
	}
	m_compute = nullptr;  // releases the cloud and the pairs
	std::lock_guard<std::mutex> lock(m_mutex);
	m_value = value;
	m_error = error;
	m_done = true;
	m_cv.notify_all();
}

const Eigen::Matrix3d& CDeferredCovariance::get()
{
	compute();  // unless begun elsewhere
	std::unique_lock<std::mutex> lock(m_mutex);
	m_cv.wait(lock, [&] { return m_done; });
	if (m_error) std::rethrow_exception(m_error);
	return m_value;
}

CLazyCovariance CLazyCovariance::then(
	std::function<Eigen::Matrix3d(const Eigen::Matrix3d&)> fn) const
{
	if (!m_deferred) return CLazyCovariance(fn(m_known));
	return CLazyCovariance(std::make_shared<CDeferredCovariance>(
		[first = m_deferred, fn = std::move(fn)] { return fn(first->get()); }));
}

}  // namespace lrgc
