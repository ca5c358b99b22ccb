#include <lrgc/common/SharedLoop.h>

namespace lrgc
{
void CSharedLoop::work()
{
	for (size_t i; (i = m_next.fetch_add(1)) < m_n;)
	{
		try
		{
			(*m_fn)(i);
		}
		catch (...)
		{
			m_errors[i] = std::current_exception();
		}
		std::lock_guard<std::mutex> lock(m_mutex);
		if (++m_done == m_n) m_cv.notify_all();
	}
}

void CSharedLoop::wait()
{
	{
		std::unique_lock<std::mutex> lock(m_mutex);
		m_cv.wait(lock, [&] { return m_done == m_n; });
	}
	for (const auto& e : m_errors)
		if (e) std::rethrow_exception(e);
}

}  // namespace lrgc
