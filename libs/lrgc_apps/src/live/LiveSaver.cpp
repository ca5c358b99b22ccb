#include "live/LiveSaver.h"

#include <lrgc/common/ThreadPriority.h>

namespace lrgc::apps
{
CLiveSaver::CLiveSaver() : m_thread([this] { threadMain(); }) {}

CLiveSaver::~CLiveSaver()
{
	{
		std::lock_guard<std::mutex> lock(m_mutex);
		m_stop = true;
	}
	m_changed.notify_all();
	m_thread.join();
}

bool CLiveSaver::idle() const
{
	std::lock_guard<std::mutex> lock(m_mutex);
	return !m_job;
}

bool CLiveSaver::trySubmit(std::function<void()> job)
{
	{
		std::lock_guard<std::mutex> lock(m_mutex);
		if (m_job || m_stop) return false;
		m_job = std::move(job);
	}
	m_changed.notify_all();
	return true;
}

void CLiveSaver::waitIdle()
{
	std::unique_lock<std::mutex> lock(m_mutex);
	m_changed.wait(lock, [this] { return !m_job; });
}

void CLiveSaver::threadMain()
{
	lowerCallingThreadPriority();  // a save may wait; the next scan's registration may not
	std::unique_lock<std::mutex> lock(m_mutex);
	while (true)
	{
		m_changed.wait(lock, [this] { return m_job || m_stop; });
		if (!m_job) return;                       // stopping, nothing left
		const std::function<void()> job = m_job;  // m_job stays set: busy until done
		lock.unlock();
		job();
		lock.lock();
		m_job = nullptr;
		m_changed.notify_all();
	}
}

}  // namespace lrgc::apps
