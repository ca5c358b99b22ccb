/* lowerCallingThreadPriority: on Linux it lowers the calling thread only. */
#include <gtest/gtest.h>
#include <lrgc/common/ThreadPriority.h>

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <thread>

namespace
{
int niceOf(pid_t tid)
{
	return ::getpriority(PRIO_PROCESS, static_cast<id_t>(tid));
}
pid_t thisThread()
{
	return static_cast<pid_t>(::syscall(SYS_gettid));
}
}  // namespace

TEST(ThreadPriority, lowersTheCallingThreadAndNoOther)
{
#if !defined(__linux__)
	GTEST_SKIP() << "per-thread priorities are Linux only";
#endif
	const pid_t mainThread = thisThread();
	const int mainBefore = niceOf(mainThread);
	int before = 0, after = 0, mainDuring = 0;
	bool lowered = false;
	std::thread t(
		[&]
		{
			before = niceOf(thisThread());
			lowered = lrgc::lowerCallingThreadPriority(3);
			after = niceOf(thisThread());
			mainDuring = niceOf(mainThread);
		});
	t.join();
	if (before + 3 > 19) GTEST_SKIP() << "the test runs at nice " << before << " already";
	EXPECT_TRUE(lowered);
	EXPECT_EQ(after, before + 3);
	EXPECT_EQ(mainDuring, mainBefore);
	EXPECT_EQ(niceOf(mainThread), mainBefore);
}
