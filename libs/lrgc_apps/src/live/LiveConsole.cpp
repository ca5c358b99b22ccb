#include "lrgc_apps/live/LiveConsole.h"

#include <unistd.h>

namespace lrgc::apps
{
CLiveConsole::CLiveConsole(std::FILE* out, bool quiet, double status_interval_s)
	: m_out(out),
	  m_quiet(quiet),
	  m_terminal(::isatty(::fileno(out)) != 0),
	  m_interval(m_terminal ? 0.25 : status_interval_s)
{
}

void CLiveConsole::clearStatusLocked()
{
	if (m_terminal && !m_status.empty()) std::fputs("\r\033[K", m_out);
}

void CLiveConsole::message(const std::string& line, bool important)
{
	if (m_quiet && !important) return;
	std::lock_guard<std::mutex> lock(m_mutex);
	clearStatusLocked();
	std::fprintf(m_out, "%s\n", line.c_str());
	if (m_terminal && !m_status.empty()) std::fputs(m_status.c_str(), m_out);
	std::fflush(m_out);
}

void CLiveConsole::status(const std::string& line, bool force)
{
	if (m_quiet) return;
	std::lock_guard<std::mutex> lock(m_mutex);
	const auto now = std::chrono::steady_clock::now();
	if (!force && std::chrono::duration<double>(now - m_lastStatus).count() < m_interval)
		return;
	m_lastStatus = now;
	if (m_terminal)
	{
		clearStatusLocked();
		m_status = line;
		std::fputs(line.c_str(), m_out);
	}
	else
		std::fprintf(m_out, "%s\n", line.c_str());
	std::fflush(m_out);
}

void CLiveConsole::endStatus()
{
	std::lock_guard<std::mutex> lock(m_mutex);
	if (m_terminal && !m_status.empty()) std::fputs("\n", m_out);
	m_status.clear();
	std::fflush(m_out);
}

}  // namespace lrgc::apps
