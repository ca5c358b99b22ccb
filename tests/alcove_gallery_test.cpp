/* A true turn in place in an aliased place, local registration alone ([MapBuilder]
 * loop_closing = false), issue 11 item 3: a long gallery lined with identical alcoves, scans
 * 1 m apart, a true 31-degree turn in place that the odometry has right. The step is
 * "suspect" (it turns more than glitch_min_turn), so the wide rotational search may run; it
 * must not overrule the odometry with an aliased pose (a museum hall came out bent by ~90 deg).
 */
#include <gtest/gtest.h>
#include <lrgc/common/se2.h>

#include <cstdio>

#include "synthetic_run.h"

using namespace lrgc::test;
using lrgc::CMetricMapBuilderLRGC;
using lrgc::TLRGCParams;

namespace
{
TLRGCParams localOnly()
{
	TLRGCParams p;
	p.builder.loop_closing = false;
	return p;
}
constexpr double kTurn = 31 * M_PI / 180;  // [rad] the true turn in place

TTrajectory galleryWalk(uint32_t seed)
{
	// Along the gallery's axis, 1 m steps, a 31-deg turn in place at x = 30, 4 m on that
	// heading, a turn back (another 31 deg) and on to x = 60.
	const Eigen::Vector2d a(5, 4), b(30, 4),
		c = b + 4 * Eigen::Vector2d(std::cos(kTurn), std::sin(kTurn));
	return makeTrajectory({a, b, c, {60, c.y()}}, 1.0, TOdometryNoise{}, seed, kTurn + 0.01);
}
}  // namespace

TEST(AlcoveGallery, trueTurnInPlaceIsNotOverruledByTheWideSearch)
{
	const CSyntheticWorld world = makeAlcoveGalleryWorld();
	size_t overrides = 0;
	double worstPhi = 0;
	for (const uint32_t seed : {1u, 2u, 3u, 4u, 5u})
	{
		const TTrajectory tr = galleryWalk(seed);
		ASSERT_GT(minClearance(world, tr.truePoses), 1.5);
		TSyntheticRunOptions opt;
		opt.scanPeriod = 0.8;  // 1 m apart at 1.25 m/s
		opt.laserSeed = seed;
		CMetricMapBuilderLRGC builder(localOnly());
		feedBuilder(builder, world, tr, opt);
		const auto e = trajectoryError(builder.trajectory(), tr.truePoses);
		std::printf(
			"[ gallery ] seed %u: max heading error %.2f deg, max position %.2f m, %zu wide "
			"overrides, %zu odometry rejected, %zu unmatched\n",
			seed, mrpt::RAD2DEG(e.maxPhi), e.maxXY, builder.stats().glitchesRecovered,
			builder.stats().odometryRejected, builder.stats().unmatchedScans);
		overrides += builder.stats().glitchesRecovered;
		worstPhi = std::max(worstPhi, e.maxPhi);
	}
	EXPECT_EQ(overrides, 0U) << "the wide search overruled a true turn";
	EXPECT_LT(worstPhi, 2 * M_PI / 180);
}
