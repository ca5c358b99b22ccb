#include <lrgc/common/HelperThread.h>

namespace lrgc
{
CHelperThread::~CHelperThread()
{
	{
		std::lock_guard<std::mutex> lock(m_mutex);
		m_stop = true;
	}
	m_cv.notify_all();
	if (m_thread.joinable()) m_thread.join();
}

void CHelperThread::post(std::function<void()> job)
{
	if (!m_threaded)
	{
		job();
		return;
	}
	{
		std::lock_guard<std::mutex> lock(m_mutex);
		m_jobs.push_back(std::move(job));
		if (!m_thread.joinable()) m_thread = std::thread([this] { threadMain(); });
	}
	m_cv.notify_all();
}

void CHelperThread::threadMain()
{
	std::unique_lock<std::mutex> lock(m_mutex);
	for (;;)
	{
		m_cv.wait(lock, [this] { return m_stop || !m_jobs.empty(); });
		if (m_jobs.empty()) return;  // stopping, nothing left
		const std::function<void()> job = std::move(m_jobs.front());
		m_jobs.pop_front();
		lock.unlock();
		job();
		lock.lock();
	}
}

}  // namespace lrgc
