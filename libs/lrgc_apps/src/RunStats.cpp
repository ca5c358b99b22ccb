#include "lrgc_apps/RunStats.h"

#include <sys/resource.h>
#include <unistd.h>

#include <ctime>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace lrgc::apps
{
double processCpuSeconds()
{
	rusage ru{};
	getrusage(RUSAGE_SELF, &ru);
	auto sec = [](const timeval& tv) { return tv.tv_sec + 1e-6 * tv.tv_usec; };
	return sec(ru.ru_utime) + sec(ru.ru_stime);
}

namespace
{
// Wall time since this process started [s], to the kernel's clock tick (10 ms): field 22 of
// /proc/self/stat (start time in ticks since boot) against CLOCK_BOOTTIME; 0 if unreadable.
double secondsSinceProcessStart()
{
	std::ifstream stat("/proc/self/stat");
	std::string text((std::istreambuf_iterator<char>(stat)), std::istreambuf_iterator<char>());
	const size_t paren = text.rfind(')');  // the command name may hold spaces
	if (paren == std::string::npos) return 0;
	std::istringstream fields(text.substr(paren + 2));
	std::string field;
	for (int i = 3; i <= 22 && fields >> field; ++i)
	{
	}
	timespec now{};
	clock_gettime(CLOCK_BOOTTIME, &now);
	const double started = std::strtod(field.c_str(), nullptr) / double(::sysconf(_SC_CLK_TCK));
	return std::max(0.0, double(now.tv_sec) + 1e-9 * double(now.tv_nsec) - started);
}
}  // namespace

void TStageTimes::startMapping()
{
	startUp = {processCpuSeconds(), secondsSinceProcessStart()};
	m_cpu0 = startUp.cpu;
	m_wall0 = std::chrono::steady_clock::now();
	m_marked = true;
}

TStageTime TStageTimes::lap()
{
	const double cpu = processCpuSeconds();
	const auto wall = std::chrono::steady_clock::now();
	const TStageTime t{cpu - m_cpu0, std::chrono::duration<double>(wall - m_wall0).count()};
	m_cpu0 = cpu;
	m_wall0 = wall;
	return t;
}

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
