/* CPU time of the calling thread, and a scoped timer adding it up: the cost of a step
 * whatever else the machine runs (wall time on a loaded machine says little). */
#pragma once

#include <time.h>

namespace lrgc
{
/** CPU time of the calling thread [s] (POSIX CLOCK_THREAD_CPUTIME_ID). */
inline double threadCpuSeconds()
{
	timespec t{};
	clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
	return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

/** Adds the thread CPU time from construction to destruction (or to stop()) to `sum` [s]. */
class CCpuTimer
{
public:
	explicit CCpuTimer(double& sum) : m_sum(&sum), m_t0(threadCpuSeconds()) {}
	~CCpuTimer() { stop(); }
	CCpuTimer(const CCpuTimer&) = delete;
	CCpuTimer& operator=(const CCpuTimer&) = delete;
	void stop()
	{
		if (m_sum) *m_sum += threadCpuSeconds() - m_t0, m_sum = nullptr;
	}

private:
	double* m_sum;
	double m_t0;
};

}  // namespace lrgc
