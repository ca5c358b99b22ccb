/* CTaskGroup: every job runs, on no more threads than asked, and wait() rethrows the first
 * failure in the order the jobs were started, after every job has ended. */
#include "TaskGroup.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <future>
#include <stdexcept>
#include <string>

using lrgc::apps::CTaskGroup;

TEST(TaskGroup, RunsEveryJobOnAtMostItsThreads)
{
	for (const size_t threads : {1u, 2u, 3u})
	{
		std::atomic<int> done{0}, running{0}, mostRunning{0};
		CTaskGroup tasks(threads);
		for (int i = 0; i < 40; ++i)
			tasks.run(
				[&]
				{
					const int now = ++running;
					int seen = mostRunning.load();
					while (now > seen && !mostRunning.compare_exchange_weak(seen, now))
					{
					}
					++done;
					--running;
				});
		tasks.wait();
		EXPECT_EQ(done.load(), 40) << threads << " threads";
		EXPECT_LE(mostRunning.load(), static_cast<int>(threads));
		tasks.run([&] { ++done; });  // the group is usable again after a wait
		tasks.wait();
		EXPECT_EQ(done.load(), 41);
	}
}

// Job 1 fails after job 2 (it waits for job 2's signal); job 3 runs all the same; wait()
// rethrows job 1's failure, the first in the order started.
TEST(TaskGroup, RethrowsTheFirstFailureInStartOrderOnceAllEnded)
{
	std::promise<void> secondFailing;
	std::atomic<bool> lastRan{false};
	CTaskGroup tasks(2);
	tasks.run([] {});
	tasks.run(
		[&]
		{
			secondFailing.get_future().wait();
			throw std::runtime_error("first");
		});
	tasks.run(
		[&]
		{
			secondFailing.set_value();
			throw std::runtime_error("second");
		});
	tasks.run([&] { lastRan = true; });
	std::string what;
	try
	{
		tasks.wait();
	}
	catch (const std::exception& e)
	{
		what = e.what();
	}
	EXPECT_EQ(what, "first");
	EXPECT_TRUE(lastRan.load());
}
