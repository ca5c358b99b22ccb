/* CGlobalSearchWorker: global localisation beside tracking (issue 29 item 3).
 *
 * A global correlation over a building-sized map takes seconds (CGlobalLocalizer); a tracking
 * thread that waited for it would leave the robot blind that long. The worker runs one search
 * at a time on its own thread while the tracking thread goes on with odometry and local
 * matching, and the tracking thread takes the result at a scan fixed by the log alone, so an
 * offline run gives the same trajectory on any machine (as CLoopClosingWorker does for loops):
 *
 *     due = t_submit + W / budget        [s of log time]
 *
 * with W the search's modelled work [ms] (TGlobalLocation::modelledMs: counted headings,
 * patch cells and poses scored, never a clock) and budget the modelled worker's work per
 * second of log ([Localization] search_budget_ms_per_s). The result is applied at the first
 * scan stamped at or after `due`. While the search runs it publishes its work so far, a lower
 * bound of W: takeIfDue(t) returns at once whenever that bound already puts `due` past t, and
 * otherwise waits for the worker (an offline replay runs faster than the log: it is then paced
 * by the modelled worker, and the time is counted as replay wait, apart from the scan's own
 * processing, which never includes a search). With `background` off a search runs inside
 * submit(): the same results, for tests.
 */
#pragma once

#include <lrgc/localization/GlobalLocalizer.h>

#include <condition_variable>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

namespace lrgc
{
struct TGlobalSearchJob
{
	std::vector<Eigen::Vector2d> patch;  //!< patch frame [m]
	TSearchArea area;                    //!< where to look (map frame)
	double submittedAt = 0;              //!< log time [s]
};

class CGlobalSearchWorker
{
public:
	/** `budgetMsPerSecond`: modelled work per second of log [ms/s], > 0. */
	CGlobalSearchWorker(const CGlobalLocalizer& localizer, double budgetMsPerSecond,
						bool background);
	/** Lets the search in hand finish and stops the thread. */
	~CGlobalSearchWorker();
	CGlobalSearchWorker(const CGlobalSearchWorker&) = delete;
	CGlobalSearchWorker& operator=(const CGlobalSearchWorker&) = delete;

	/** Starts a search; requires !busy(). Without a thread, runs it now. */
	void submit(TGlobalSearchJob job);
	/** A search was submitted and its result not yet taken. */
	bool busy() const { return m_busy; }
	/** The search's result if it is due at log time `now` [s] (see the header); nullopt if
	 * none is. Rethrows what the search threw. */
	std::optional<TGlobalLocation> takeIfDue(double now);

	/** Live use: takeIfDue() hands the result over as soon as the search has ended and never
	 * waits (the schedule then depends on the machine, as a live run's does anyway). */
	void setTakeWhenReady(bool whenReady) { m_whenReady = whenReady; }

	/** Time takeIfDue() waited for the real worker to catch up with the modelled one [s]. */
	double waitedSeconds() const { return m_waited; }
	double longestWaitSeconds() const { return m_longestWait; }
	/** Searches run on the caller's thread (inside submit(): `background` off). */
	size_t searchesOnCallerThread() const { return m_onCaller; }

private:
	double dueAt(double modelledMs) const { return m_submittedAt + modelledMs / m_budget; }
	TGlobalLocation run(const TGlobalSearchJob& job);
	void threadMain();

	const CGlobalLocalizer& m_localizer;
	const double m_budget;  //!< [ms of modelled work per s of log]
	bool m_busy = false;
	bool m_whenReady = false;  //!< setTakeWhenReady()
	double m_submittedAt = 0;
	double m_waited = 0, m_longestWait = 0;
	size_t m_onCaller = 0;

	std::mutex m_mutex;  // guards what follows
	std::condition_variable m_cv;
	std::optional<TGlobalSearchJob> m_job;    //!< handed over, not yet started
	double m_progressMs = 0;                  //!< modelled work so far of the search running
	std::optional<TGlobalLocation> m_result;  //!< of the last search, not yet taken
	std::exception_ptr m_error;
	bool m_stop = false;
	std::thread m_thread;  // last: started once the rest is constructed
};

}  // namespace lrgc
