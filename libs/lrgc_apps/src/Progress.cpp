#include "Progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>

namespace lrgc::apps
{
namespace
{
std::string clockText(double seconds)
{
	if (!std::isfinite(seconds) || seconds < 0) return "--:--";
	const long s = std::lround(seconds);
	char buf[32];
	if (s >= 3600)
		std::snprintf(buf, sizeof(buf), "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
	else
		std::snprintf(buf, sizeof(buf), "%02ld:%02ld", s / 60, s % 60);
	return buf;
}
}  // namespace

CProgress::CProgress(std::FILE* out, bool quiet, double lineIntervalSeconds)
	: CProgress(out,
				quiet ? Mode::Quiet : (::isatty(::fileno(out)) ? Mode::Terminal : Mode::Lines),
				lineIntervalSeconds)
{
}

CProgress::CProgress(std::FILE* out, Mode mode, double lineIntervalSeconds)
	: m_out(out), m_mode(mode), m_lineInterval(lineIntervalSeconds)
{
	m_start = m_lastDraw = std::chrono::steady_clock::now();
}

std::string CProgress::format(double fraction, size_t scans, const std::string& extra) const
{
	fraction = std::clamp(fraction, 0.0, 1.0);
	const double elapsed =
		std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
	const double rate = elapsed > 0 ? scans / elapsed : 0;
	const double left = fraction > 1e-6 ? elapsed * (1 - fraction) / fraction : NAN;
	char buf[256];
	if (m_mode == Mode::Terminal)
	{
		constexpr int width = 30;
		const int filled = static_cast<int>(std::lround(fraction * width));
		std::string bar(filled, '#');
		bar.resize(width, '.');
		std::snprintf(buf, sizeof(buf), "\r[%s] %5.1f%%  %zu scans  %.0f scans/s  %s left  %s",
					  bar.c_str(), 100 * fraction, scans, rate, clockText(left).c_str(),
					  extra.c_str());
	}
	else
		std::snprintf(buf, sizeof(buf),
					  "progress: %.1f%% %zu scans %.0f scans/s elapsed %s left %s %s\n",
					  100 * fraction, scans, rate, clockText(elapsed).c_str(),
					  clockText(left).c_str(), extra.c_str());
	return buf;
}

void CProgress::update(double fraction, size_t scans, const std::string& extra)
{
	if (m_mode == Mode::Quiet) return;
	const auto now = std::chrono::steady_clock::now();
	const double since = std::chrono::duration<double>(now - m_lastDraw).count();
	if (since < (m_mode == Mode::Terminal ? 0.2 : m_lineInterval)) return;
	m_lastDraw = now;
	std::fputs(format(fraction, scans, extra).c_str(), m_out);
	if (m_mode == Mode::Terminal) std::fputs("\033[K", m_out);  // clear to end of line
	std::fflush(m_out);
	m_drawn = true;
}

void CProgress::finish(double fraction, size_t scans, const std::string& extra)
{
	if (m_mode == Mode::Quiet) return;
	std::fputs(format(fraction, scans, extra).c_str(), m_out);
	if (m_mode == Mode::Terminal) std::fputs("\033[K\n", m_out);
	std::fflush(m_out);
}

}  // namespace lrgc::apps
