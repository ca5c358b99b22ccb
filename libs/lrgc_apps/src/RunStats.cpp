#include "lrgc_apps/RunStats.h"

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace lrgc::apps
{
namespace
{
double processCpuSeconds()
{
	rusage ru{};
	getrusage(RUSAGE_SELF, &ru);
	auto sec = [](const timeval& tv) { return tv.tv_sec + 1e-6 * tv.tv_usec; };
	return sec(ru.ru_utime) + sec(ru.ru_stime);
}
}  // namespace

CRunClock::CRunClock() : m_wall0(std::chrono::steady_clock::now()), m_cpu0(processCpuSeconds())
{
}

double CRunClock::wallSeconds() const
{
	return std::chrono::duration<double>(std::chrono::steady_clock::now() - m_wall0).count();
}

double CRunClock::cpuSeconds() const
{
	return processCpuSeconds() - m_cpu0;
}

double CRunClock::peakRssMiB()
{
	rusage ru{};
	getrusage(RUSAGE_SELF, &ru);
	return ru.ru_maxrss / 1024.0;  // Linux reports KiB
}

TLatencySummary summarizeLatencies(std::vector<double> v)
{
	TLatencySummary s;
	if (v.empty()) return s;
	std::sort(v.begin(), v.end());
	auto rank = [&](double p)
	{
		const size_t k = static_cast<size_t>(std::ceil(p * v.size()));
		return v[std::clamp<size_t>(k, 1, v.size()) - 1];
	};
	s.median_ms = rank(0.5);
	s.p99_ms = rank(0.99);
	s.max_ms = v.back();
	s.mean_ms = std::accumulate(v.begin(), v.end(), 0.0) / v.size();
	return s;
}

}  // namespace lrgc::apps
