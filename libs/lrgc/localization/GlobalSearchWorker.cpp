#include <lrgc/localization/GlobalSearchWorker.h>

#include <mrpt/core/exceptions.h>

#include <algorithm>
#include <chrono>

namespace lrgc
{
CGlobalSearchWorker::CGlobalSearchWorker(const CGlobalLocalizer& localizer,
										 double budgetMsPerSecond, bool background)
	: m_localizer(localizer), m_budget(budgetMsPerSecond)
{
	ASSERTMSG_(budgetMsPerSecond > 0, "CGlobalSearchWorker: the budget must be > 0 ms/s");
	if (background) m_thread = std::thread([this] { threadMain(); });
}

CGlobalSearchWorker::~CGlobalSearchWorker()
{
	if (!m_thread.joinable()) return;
	{
		std::lock_guard lock(m_mutex);
		m_stop = true;
	}
	m_cv.notify_all();
	m_thread.join();
}

TGlobalLocation CGlobalSearchWorker::run(const TGlobalSearchJob& job)
{
	return m_localizer.locate(job.patch, job.area,
							  [this](double ms)
							  {
								  {
									  std::lock_guard lock(m_mutex);
									  m_progressMs = ms;
								  }
								  m_cv.notify_all();
							  });
}

void CGlobalSearchWorker::submit(TGlobalSearchJob job)
{
	ASSERTMSG_(!m_busy, "CGlobalSearchWorker::submit: a search is already in hand");
	m_busy = true;
	m_submittedAt = job.submittedAt;
	if (!m_thread.joinable())
	{
		++m_onCaller;
		try
		{
			m_result = run(job);
		}
		catch (...)
		{
			m_error = std::current_exception();
		}
		return;
	}
	{
		std::lock_guard lock(m_mutex);
		m_progressMs = 0;
		m_job = std::move(job);
	}
	m_cv.notify_all();
}

std::optional<TGlobalLocation> CGlobalSearchWorker::takeIfDue(double now)
{
	if (!m_busy) return std::nullopt;
	std::unique_lock lock(m_mutex);
	if (m_whenReady && !m_result && !m_error) return std::nullopt;
	// Decided: the search is over, or its work so far already puts it past `now`.
	const auto decided = [&]
	{ return m_result || m_error || (!m_job && dueAt(m_progressMs) > now); };
	if (!decided())
	{
		const auto t0 = std::chrono::steady_clock::now();
		m_cv.wait(lock, decided);
		const double w =
			std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
		m_waited += w, m_longestWait = std::max(m_longestWait, w);
	}
	if (m_error)
	{
		m_busy = false;
		std::rethrow_exception(std::exchange(m_error, nullptr));
	}
	if (!m_result || (!m_whenReady && dueAt(m_result->modelledMs) > now)) return std::nullopt;
	m_busy = false;
	auto out = std::move(m_result);
	m_result.reset();
	return out;
}

void CGlobalSearchWorker::threadMain()
{
	std::unique_lock lock(m_mutex);
	for (;;)
	{
		m_cv.wait(lock, [&] { return m_stop || m_job; });
		if (m_stop) return;
		const TGlobalSearchJob job = std::move(*m_job);
		m_job.reset();
		lock.unlock();
		std::optional<TGlobalLocation> result;
		std::exception_ptr error;
		try
		{
			result = run(job);
		}
		catch (...)
		{
			error = std::current_exception();
		}
		lock.lock();
		m_result = std::move(result), m_error = error;
		m_cv.notify_all();
	}
}

}  // namespace lrgc
