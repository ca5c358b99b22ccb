#include "TaskGroup.h"

namespace lrgc::apps
{
CTaskGroup::~CTaskGroup()
{
	joinAll();
}

void CTaskGroup::run(std::function<void()> job)
{
	std::lock_guard<std::mutex> lock(m_mutex);
	m_queue.emplace_back(m_failures.size(), std::move(job));
	m_failures.emplace_back();
	// A thread that found the queue empty has left (or is leaving): start another if fewer
	// than the maximum are busy.
	if (m_busyThreads < m_maxThreads)
	{
		++m_busyThreads;
		m_threads.emplace_back([this] { threadMain(); });
	}
}

void CTaskGroup::threadMain()
{
	std::unique_lock<std::mutex> lock(m_mutex);
	while (!m_queue.empty())
	{
		auto [index, job] = std::move(m_queue.front());
		m_queue.pop_front();
		lock.unlock();
		std::exception_ptr failure;
		try
		{
			job();
		}
		catch (...)
		{
			failure = std::current_exception();
		}
		lock.lock();
		m_failures[index] = failure;
	}
	--m_busyThreads;
}

void CTaskGroup::joinAll()
{
	for (auto& t : m_threads)
		if (t.joinable()) t.join();
	m_threads.clear();
}

void CTaskGroup::wait()
{
	joinAll();
	std::exception_ptr first;
	{
		std::lock_guard<std::mutex> lock(m_mutex);
		for (const auto& f : m_failures)
			if (f && !first) first = f;
		m_failures.clear();
	}
	if (first) std::rethrow_exception(first);
}

}  // namespace lrgc::apps
