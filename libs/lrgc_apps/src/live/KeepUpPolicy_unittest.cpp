#include <gtest/gtest.h>
#include "live/KeepUpPolicy.h"

#include <algorithm>
#include <deque>

using lrgc::apps::CKeepUpPolicy;

TEST(KeepUpPolicy, MapsEveryScanWithinTheLimit)
{
	CKeepUpPolicy p(5);
	for (size_t waiting = 0; waiting <= 5; ++waiting) EXPECT_TRUE(p.shouldMap(waiting));
	EXPECT_FALSE(p.behind());
	EXPECT_EQ(p.skippedTotal(), 0u);
}

TEST(KeepUpPolicy, ZeroLimitNeverSkips)
{
	CKeepUpPolicy p(0);
	for (size_t waiting = 0; waiting < 10000; waiting += 97) EXPECT_TRUE(p.shouldMap(waiting));
	EXPECT_EQ(p.skippedTotal(), 0u);
}

TEST(KeepUpPolicy, SkipsFloorOfBacklogOverLimitBetweenMappedScans)
{
	CKeepUpPolicy p(10);
	// 35 waiting: k = 3 skips, then one mapped, then again.
	EXPECT_FALSE(p.shouldMap(35));
	EXPECT_TRUE(p.behind());
	EXPECT_FALSE(p.shouldMap(35));
	EXPECT_FALSE(p.shouldMap(35));
	EXPECT_TRUE(p.shouldMap(35));
	EXPECT_FALSE(p.shouldMap(35));
	EXPECT_EQ(p.skippedTotal(), 4u);
	EXPECT_EQ(p.skippedThisEpisode(), 4u);
	// Back under the limit: caught up, the episode count restarts at the next episode.
	EXPECT_TRUE(p.shouldMap(10));
	EXPECT_FALSE(p.behind());
	EXPECT_FALSE(p.shouldMap(11));
	EXPECT_EQ(p.skippedThisEpisode(), 1u);
	EXPECT_EQ(p.skippedTotal(), 5u);
}

// A simulated run: scans arrive every period, mapping one takes `s` periods. The backlog must
// stay bounded near M (s - 1) whatever s is, and every scan is either mapped or skipped.
TEST(KeepUpPolicy, BacklogStaysBoundedForAnySlowness)
{
	for (const double slowness : {0.5, 1.5, 3.0, 10.0, 40.0})
	{
		const size_t M = 8;
		CKeepUpPolicy p(M);
		std::deque<int> queue;
		double busyUntil = 0;
		size_t mapped = 0, maxBacklog = 0;
		const int arrivals = 20000;
		for (int t = 0; t < arrivals; ++t)
		{
			queue.push_back(t);
			while (!queue.empty() && busyUntil <= t)
			{
				queue.pop_front();
				if (p.shouldMap(queue.size()))
				{
					++mapped;
					busyUntil = std::max(busyUntil, double(t)) + slowness;
				}
			}
			maxBacklog = std::max(maxBacklog, queue.size());
		}
		EXPECT_EQ(mapped + p.skippedTotal() + queue.size(), size_t(arrivals)) << slowness;
		// Equilibrium M (s - 1), plus the s scans that arrive while one is mapped, plus M.
		const double bound = (M + 1) * std::max(1.0, slowness) + M;
		EXPECT_LE(double(maxBacklog), bound) << "slowness " << slowness;
		if (slowness <= 1.0)
			EXPECT_EQ(p.skippedTotal(), 0u);
		else
			EXPECT_GT(p.skippedTotal(), 0u);
	}
}
