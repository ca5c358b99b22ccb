#include <lrgc/common/SharedLoop.h>

#include <memory>

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

void runShared(CHelperThread& helper, size_t n, const std::function<void(size_t)>& fn)
{
	// Held by the helper's job too: it may start after the owner has finished the loop.
	auto loop = std::make_shared<CSharedLoop>(n, fn);
	if (n > 1 && helper.threaded()) helper.post([loop] { loop->work(); });
	loop->work();
	loop->wait();
}

}  // namespace lrgc
