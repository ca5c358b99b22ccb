/* CHelperThread: jobs run in the order posted, on another thread (or at once without one),
 * and the destructor lets every queued job run. */
#include <gtest/gtest.h>
#include <lrgc/common/HelperThread.h>

#include <memory>
#include <mutex>
#include <thread>
#include <vector>

using lrgc::CHelperThread;

TEST(HelperThread, runsEveryJobInOrderOnItsThreadAndTheDestructorWaitsForThem)
{
	auto order = std::make_shared<std::vector<int>>();
	auto mutex = std::make_shared<std::mutex>();
	std::vector<std::thread::id> threads(50);
	{
		CHelperThread helper;
		EXPECT_TRUE(helper.threaded());
		for (int i = 0; i < 50; ++i)
			helper.post(
				[=, &threads]
				{
					const std::lock_guard<std::mutex> lock(*mutex);
					order->push_back(i);
					threads[i] = std::this_thread::get_id();
				});
	}  // the queued jobs run to their end here
	ASSERT_EQ(order->size(), 50U);
	for (int i = 0; i < 50; ++i)
	{
		EXPECT_EQ((*order)[i], i);
		EXPECT_NE(threads[i], std::this_thread::get_id());
		EXPECT_EQ(threads[i], threads[0]);  // one thread
	}
}

TEST(HelperThread, withoutAThreadAJobRunsInsidePost)
{
	CHelperThread helper(false);
	EXPECT_FALSE(helper.threaded());
	std::thread::id ranOn;
	int runs = 0;
	helper.post([&] { ranOn = std::this_thread::get_id(), ++runs; });
	EXPECT_EQ(runs, 1);
	EXPECT_EQ(ranOn, std::this_thread::get_id());
}
