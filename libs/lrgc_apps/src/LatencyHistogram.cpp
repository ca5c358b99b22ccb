/* CLatencyHistogram (see LatencyHistogram.h). */
#include "LatencyHistogram.h"

#include <algorithm>
#include <cmath>

namespace lrgc::apps
{
void CLatencyHistogram::add(double ms)
{
	const double bin = ms > kFirstMs ? std::log(ms / kFirstMs) / std::log(kRatio) : 0;
	++m_bins[std::min<size_t>(static_cast<size_t>(bin), kBins - 1)];
	++m_count;
	m_sum += ms;
	m_max = std::max(m_max, ms);
}

TLatencySummary CLatencyHistogram::summary() const
{
	TLatencySummary s;
	if (m_count == 0) return s;
	// Nearest rank k = ceil(p n), as summarizeLatencies; the bin's geometric middle, at most
	// the exact maximum.
	auto rank = [&](double p)
	{
		const uint64_t k = std::clamp<uint64_t>(std::ceil(p * m_count), 1, m_count);
		uint64_t seen = 0;
		size_t b = 0;
		while (b + 1 < kBins && (seen += m_bins[b]) < k) ++b;
		return std::min(m_max, kFirstMs * std::pow(kRatio, b + 0.5));
	};
	s.median_ms = rank(0.5);
	s.p99_ms = rank(0.99);
	s.max_ms = m_max;
	s.mean_ms = m_sum / m_count;
	return s;
}

}  // namespace lrgc::apps
