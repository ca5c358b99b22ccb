/* Progress report of a long run on stderr: a bar redrawn in place on a terminal (done
 * fraction, scans per second, time left), a plain line every few seconds otherwise (logs, CI),
 * nothing when quiet. */
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

namespace lrgc::apps
{
class CProgress
{
public:
	enum class Mode
	{
		Terminal,
		Lines,
		Quiet
	};
	/** Mode from the stream: Terminal if it is a tty, Lines otherwise; Quiet if quiet. */
	CProgress(std::FILE* out, bool quiet, double lineIntervalSeconds = 10.0);
	CProgress(std::FILE* out, Mode mode, double lineIntervalSeconds);

	/** fraction in [0,1] of the input consumed; scans processed so far; extra text. */
	void update(double fraction, size_t scans, const std::string& extra = {});
	/** Final line (newline after a bar): `fraction` of the input consumed, 1 only for a run
	 * that read its input to the end (an interrupted one shows where it stopped). */
	void finish(double fraction, size_t scans, const std::string& extra = {});
	Mode mode() const { return m_mode; }

private:
	std::string format(double fraction, size_t scans, const std::string& extra) const;
	std::FILE* m_out;
	Mode m_mode;
	double m_lineInterval;
	std::chrono::steady_clock::time_point m_start, m_lastDraw;
	bool m_drawn = false;
};

}  // namespace lrgc::apps
