#include <lrgc/common/ThreadPriority.h>

#if defined(__linux__)
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#endif

namespace lrgc
{
bool lowerCallingThreadPriority(int increment)
{
#if defined(__linux__)
	// PRIO_PROCESS with a thread id addresses that one thread on Linux (setpriority(2), BUGS).
	const auto tid = static_cast<id_t>(::syscall(SYS_gettid));
	errno = 0;
	const int nice = ::getpriority(PRIO_PROCESS, tid);
	if (errno != 0) return false;
	return ::setpriority(PRIO_PROCESS, tid, nice + increment) == 0;
#else
	(void)increment;
	return false;
#endif
}

}  // namespace lrgc
