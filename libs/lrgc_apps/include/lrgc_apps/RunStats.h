/* Measurements of one run for stats.json and timing.csv: per-scan latency, wall and CPU time,
 * peak resident memory. */
#pragma once

#include <chrono>
#include <string>
#include <vector>

namespace lrgc::apps
{
struct TLatencySummary
{
	double median_ms = 0, p99_ms = 0, max_ms = 0, mean_ms = 0;
};

class CRunClock
{
public:
	CRunClock();
	double wallSeconds() const;
	/** CPU time (user + system) of this process since the clock was made [s]. */
	double cpuSeconds() const;
	/** Peak resident set size of this process so far [MiB] (getrusage ru_maxrss). */
	static double peakRssMiB();

private:
	std::chrono::steady_clock::time_point m_wall0;
	double m_cpu0;
};

/** Order statistics of latencies [ms]; percentiles by nearest rank. */
TLatencySummary summarizeLatencies(std::vector<double> latenciesMs);

}  // namespace lrgc::apps
