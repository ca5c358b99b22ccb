/* CDeferredCovariance and CScanMatcher::matchDeferred: a covariance computed later, on any
 * thread, is the one a match computes at once, bit for bit. */
#include <gtest/gtest.h>
#include <lrgc/scan_matching/DeferredCovariance.h>
#include <lrgc/scan_matching/ScanMatcher.h>

#include <atomic>
#include <cmath>
#include <random>
#include <stdexcept>
#include <thread>

#include "ScanMatcher_unittest.h"
#include "synthetic_world.h"

using namespace lrgc;
using namespace lrgc::test;

TEST(DeferredCovariance, computedOnceWhoeverAsksAndChained)
{
	std::atomic<int> calls{0};
	auto d = std::make_shared<CDeferredCovariance>(
		[&]
		{
			++calls;
			return Eigen::Matrix3d::Constant(2.0);
		});
	const CLazyCovariance lazy(d);
	const CLazyCovariance doubled = lazy.then([](const Eigen::Matrix3d& c) { return 2 * c; });
	EXPECT_FALSE(d->claimed());
	std::thread helper([&] { d->compute(); });
	EXPECT_EQ(lazy.get(), Eigen::Matrix3d::Constant(2.0));
	helper.join();
	EXPECT_EQ(calls.load(), 1);
	EXPECT_EQ(doubled.get(), Eigen::Matrix3d::Constant(4.0));
	CLazyCovariance settled = doubled;
	settled.settle();
	EXPECT_FALSE(settled.deferred());
	EXPECT_EQ(settled.get(), Eigen::Matrix3d::Constant(4.0));
	// Known ones apply then() at once.
	EXPECT_EQ(CLazyCovariance(Eigen::Matrix3d::Identity())
				  .then([](const Eigen::Matrix3d& c) { return 3 * c; })
				  .get(),
			  3 * Eigen::Matrix3d::Identity());
}

TEST(DeferredCovariance, rethrowsWhatTheComputationThrew)
{
	CDeferredCovariance d([]() -> Eigen::Matrix3d { throw std::runtime_error("bad"); });
	d.compute();
	EXPECT_THROW(d.get(), std::runtime_error);
}

TEST(DeferredCovariance, matchDeferredGivesTheMatchsCovarianceBitForBit)
{
	std::mt19937 rng(5);
	const TScanMatcherParams params;
	const CScanMatcher matcher(params);
	int compared = 0;
	for (int t = 0; t < 5; ++t)
	{
		const auto world = makeRoomWorld(40 + t);
		const auto [a, b] = roomPosePair(world, rng, 0.3, 10 * kDeg);
		const TLaserSimParams laser;
		const auto scanA = simulateScan(world, a, laser, rng);
		const auto scanB = simulateScan(world, b, laser, rng);
		const TPose2D guess = perturb(between(a, b), 0.05, 2 * kDeg, rng);
		const auto ref =
			std::make_shared<const CReferenceCloud>(CReferenceCloud::fromScan(scanA, params));
		const auto now = matcher.match(*ref, scanB, guess);
		const auto later = matcher.matchDeferred(ref, scanB, guess);
		ASSERT_EQ(now.has_value(), later.has_value());
		if (!now) continue;
		ASSERT_TRUE(later->deferredCov && !now->deferredCov);
		EXPECT_TRUE(later->cov.array().isNaN().all());  // not to be read
		std::thread other([d = later->deferredCov] { d->compute(); });
		other.join();
		EXPECT_EQ(later->covariance().get(), now->cov);
		EXPECT_EQ(now->covariance().get(), now->cov);
		++compared;
	}
	EXPECT_GE(compared, 3);
}
