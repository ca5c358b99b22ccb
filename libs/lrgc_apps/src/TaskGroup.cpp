#include "TaskGroup.h"

#include <exception>

namespace lrgc::apps
{
CTaskGroup::~CTaskGroup()
{
	for (auto& job : m_jobs)
		if (job.valid()) job.wait();
}

void CTaskGroup::run(std::function<void()> job)
{
	m_jobs.push_back(std::async(std::launch::async, std::move(job)));
}

void CTaskGroup::wait()
{
	std::exception_ptr first;
	for (auto& job : m_jobs)
	{
		try
		{
			job.get();
		}
		catch (...)
		{
			if (!first) first = std::current_exception();
		}
	}
	m_jobs.clear();
	if (first) std::rethrow_exception(first);
}

}  // namespace lrgc::apps
