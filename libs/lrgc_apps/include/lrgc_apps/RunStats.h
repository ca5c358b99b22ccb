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

/** CPU time (user + system) of this process so far, all threads [s] (getrusage). */
double processCpuSeconds();

/** Process CPU [s] and wall [s] of one stage of a run. */
struct TStageTime
{
	double cpu = 0, wall = 0;
};

/** Where a run's time went, stage by stage (stats.json "stages"). The stages follow each
 * other without a gap: each lap() ends one and starts the next, so their process CPU times
 * add up to the process's CPU time at the last lap. Within mapping, the mapping thread's own
 * CPU time is split by the app's and the map builder's timers (CLOCK_THREAD_CPUTIME_ID). */
struct TStageTimes
{
	/** Ends the start-up (from the process's start: loading the libraries, MRPT's class
	 * registration, the configuration, opening the input) and starts the mapping. */
	void startMapping();
	/** The process CPU and wall since the last mark; the next stage starts now. */
	TStageTime lap();
	bool started() const { return m_marked; }

	TStageTime startUp, mapping, finalOptimization, outputs;
	/** The mapping thread during the mapping: all of it, reading the input (parsing,
	 * gunzip), and feeding the builder; from the builder, its placement of scans (keyframes,
	 * window links and solve, loop results applied), all [s] of CPU. */
	double mappingThreadCpu = 0, inputCpu = 0, feedCpu = 0, placementCpu = 0;
	/** The loop-closing worker thread's CPU during the mapping [s]. */
	double loopWorkerCpu = 0;

private:
	bool m_marked = false;
	double m_cpu0 = 0;
	std::chrono::steady_clock::time_point m_wall0;
};

/** Order statistics of latencies [ms]; percentiles by nearest rank. */
TLatencySummary summarizeLatencies(std::vector<double> latenciesMs);

}  // namespace lrgc::apps
