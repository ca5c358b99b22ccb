/* CLatencyHistogram: order statistics of latencies in fixed memory, for runs of hours. */
#pragma once

#include <lrgc_apps/RunStats.h>

#include <array>
#include <cstddef>
#include <cstdint>

namespace lrgc::apps
{
/** Latencies [ms] in 1 % wide bins (log-spaced from 1 us to 6 hours): order statistics within
 * 1 % in a fixed 30 kB, however many scans; the mean and the maximum are exact. */
class CLatencyHistogram
{
public:
	void add(double ms);
	size_t count() const { return m_count; }
	/** Median and p99 by nearest rank (the geometric middle of their bin), exact max, mean. */
	TLatencySummary summary() const;
	double max() const { return m_max; }

private:
	static constexpr size_t kBins = 3000;
	static constexpr double kFirstMs = 1e-3, kRatio = 1.01;
	std::array<uint64_t, kBins> m_bins{};
	size_t m_count = 0;
	double m_sum = 0, m_max = 0;
};

}  // namespace lrgc::apps
