/* CSharedLoop: every iteration exactly once whichever threads take part; errors rethrown by
 * index; a thread joining after the end never calls fn. */
#include <gtest/gtest.h>
#include <lrgc/common/SharedLoop.h>

#include <atomic>
#include <stdexcept>
#include <thread>
#include <vector>

using lrgc::CSharedLoop;

TEST(SharedLoop, everyIterationRunsOnceWhicheverThreadsTakePart)
{
	const size_t n = 5000;
	std::vector<std::atomic<int>> runs(n);
	std::atomic<int> onJoiner{0};
	const std::thread::id owner = std::this_thread::get_id();
	const std::function<void(size_t)> fn = [&](size_t i)
	{
		runs[i].fetch_add(1);
		if (std::this_thread::get_id() != owner) onJoiner.fetch_add(1);
	};
	CSharedLoop loop(n, fn);
	std::thread joiner([&] { loop.work(); });
	loop.work();
	loop.wait();
	joiner.join();
	for (size_t i = 0; i < n; ++i) ASSERT_EQ(runs[i].load(), 1) << "iteration " << i;
	EXPECT_TRUE(loop.exhausted());
	EXPECT_LE(onJoiner.load(), int(n));
	// A thread joining after the end finds nothing left and does not call fn.
	loop.work();
	for (size_t i = 0; i < n; ++i) ASSERT_EQ(runs[i].load(), 1);
}

TEST(SharedLoop, waitRethrowsTheErrorOfTheLowestIterationAfterAllFinished)
{
	std::atomic<int> ran{0};
	const std::function<void(size_t)> fn = [&](size_t i)
	{
		ran.fetch_add(1);
		if (i == 7 || i == 3) throw std::runtime_error("iteration " + std::to_string(i));
	};
	CSharedLoop loop(10, fn);
	loop.work();
	try
	{
		loop.wait();
		FAIL() << "no error rethrown";
	}
	catch (const std::runtime_error& e)
	{
		EXPECT_STREQ(e.what(), "iteration 3");
	}
	EXPECT_EQ(ran.load(), 10);  // an error does not stop the other iterations
}
