/* CLiveConsole: what a live run tells its user on stderr, from several threads.
 *
 * Messages (sensor failures and recoveries, falling behind, saves) are whole lines, printed at
 * once; on a terminal the status line is cleared first and redrawn after. The status line
 * (scans received, scans mapped, queue depth, loops closed, ...) is redrawn in place about 4
 * times a second on a terminal and printed as a plain line every status_interval_s otherwise.
 * Quiet: no status line and no informational messages; problems are still printed.
 */
#pragma once

#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>

namespace lrgc::apps
{
class CLiveConsole
{
public:
	CLiveConsole(std::FILE* out, bool quiet, double status_interval_s);

	/** A line; `important` ones (problems) are printed even when quiet. Thread-safe. */
	void message(const std::string& line, bool important = true);
	/** The status line, printed if its period has passed (or `force`). Thread-safe. */
	void status(const std::string& line, bool force = false);
	/** Ends a status line drawn in place (newline). */
	void endStatus();

private:
	void clearStatusLocked();
	std::FILE* m_out;
	bool m_quiet, m_terminal;
	double m_interval;
	std::mutex m_mutex;
	std::chrono::steady_clock::time_point m_lastStatus{};
	std::string m_status;  //!< last status drawn in place (terminal)
};

}  // namespace lrgc::apps
