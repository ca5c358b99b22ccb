/* [MapBuilder] min_range_m cleans a robot's own posts out of the map: the laser of a synthetic
 * run sees, besides the room, two posts of the robot 0.15 m away at +-60 degrees (21 beams
 * each), in every scan. Without the limit they are matched and drawn into the grid at every
 * keyframe (later rays clear some); with min_range_m = 0.3 m no keyframe point, no grid cell
 * and no saved keyframe observation holds them, and the readings dropped are counted. */
#include <gtest/gtest.h>

#include <lrgc/common/se2.h>
#include <lrgc/map_builder/CMetricMapBuilderLRGC.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CObservationOdometry.h>

#include "synthetic_run.h"

namespace
{
using mrpt::math::TPose2D;
using namespace lrgc::test;

constexpr double kPostRange = 0.15;  // [m]
constexpr int kBeamsPerPost = 21;

struct TPostsRun
{
	CSyntheticWorld world = makeRoomWorld(5, 0);
	TTrajectory tr = makeTrajectory({{1.5, 3.5}, {5.5, 3.5}, {5.5, 5.8}, {1.2, 5.8}}, 0.05,
									TOdometryNoise{}, 21);
	TLaserSimParams laser;  // 180 deg, 361 beams: 0.5 deg apart
	size_t postReadings = 0;

	/** Feeds every step, each scan with the posts at beams 60 +-5 deg either side of ahead. */
	void feed(lrgc::CMetricMapBuilderLRGC& builder)
	{
		std::mt19937 rng(3);
		for (size_t k = 0; k < tr.truePoses.size(); ++k)
		{
			const auto t = syntheticStepTime(k, 0.2);
			auto odo = mrpt::obs::CObservationOdometry::Create();
			odo->timestamp = t;
			odo->odometry = mrpt::poses::CPose2D(tr.odometryPoses[k]);
			builder.processObservation(odo);
			auto obs = laserObservationFromScan(
				simulateScan(world, tr.truePoses[k], laser, rng), laser, t);
			for (const int centre : {60, 300})  // beam index of -60 and +60 deg
				for (int i = centre - kBeamsPerPost / 2; i <= centre + kBeamsPerPost / 2; ++i)
				{
					obs->setScanRange(i, static_cast<float>(kPostRange));
					obs->setScanRangeValidity(i, true);
					++postReadings;
				}
			builder.processObservation(obs);
		}
		builder.finish();
	}
};

/** Keyframes (of the builder) whose grid cell at either post's place is occupied. */
size_t keyframesWithPostsInGrid(const lrgc::CMetricMapBuilderLRGC& builder)
{
	const auto grid = builder.buildOccupancyGrid();
	size_t n = 0;
	for (size_t i = 0; i < builder.keyframes().size(); ++i)
	{
		const TPose2D p = builder.graph().pose(i);
		bool seen = false;
		for (const double bearing : {-M_PI / 3, M_PI / 3})
		{
			const auto post = lrgc::transformPoint(
				p, {kPostRange * std::cos(bearing), kPostRange * std::sin(bearing)});
			seen |= grid->getPos(float(post.x()), float(post.y())) < 0.4f;  // p(free) < 0.4
		}
		n += seen ? 1 : 0;
	}
	return n;
}

size_t keyframePointsWithin(const lrgc::CMetricMapBuilderLRGC& builder, double r)
{
	size_t n = 0;
	for (const auto& kf : builder.keyframes())
		for (const auto& p : kf.scan.points) n += p.norm() < r ? 1 : 0;
	return n;
}
}  // namespace

TEST(RobotPosts, MinRangeCleansTheRobotsOwnPostsFromTheMap)
{
	TPostsRun run;
	for (const auto& p : run.tr.truePoses)  // the room itself is never that close
		ASSERT_GT(run.world.distanceToNearest({p.x, p.y}), 0.5);

	lrgc::CMetricMapBuilderLRGC dirty;
	run.feed(dirty);
	ASSERT_GT(dirty.keyframes().size(), 10u);
	// The failure the limit is for: posts in every keyframe's points and all over the grid.
	EXPECT_GE(keyframePointsWithin(dirty, 0.3), dirty.keyframes().size() * 2 * kBeamsPerPost);
	EXPECT_GT(keyframesWithPostsInGrid(dirty), dirty.keyframes().size() / 5);
	EXPECT_EQ(dirty.lasers().rangeLimitedReadings(), 0u);

	lrgc::TLRGCParams params;
	params.builder.min_range_m = 0.3;
	lrgc::CMetricMapBuilderLRGC clean(params);
	run.postReadings = 0;
	run.feed(clean);
	ASSERT_GT(clean.keyframes().size(), 10u);
	EXPECT_EQ(keyframePointsWithin(clean, 0.3), 0u);
	EXPECT_EQ(keyframesWithPostsInGrid(clean), 0u);
	EXPECT_EQ(clean.lasers().rangeLimitedReadings(), run.postReadings);
	// The saved keyframes (CSimpleMap) hold the cleaned scans too.
	mrpt::maps::CSimpleMap sm;
	clean.getCurrentlyBuiltMap(sm);
	ASSERT_EQ(sm.size(), clean.keyframes().size());
	const auto [pose, sf] = sm.get(0);
	const auto obs = sf->getObservationByClass<mrpt::obs::CObservation2DRangeScan>();
	ASSERT_TRUE(obs);
	EXPECT_FALSE(obs->getScanRangeValidity(300));
	EXPECT_TRUE(obs->getScanRangeValidity(180));
	// And the map is right: every pose within a few cm of the truth.
	const TTrajectoryError err = trajectoryError(clean.trajectory(), run.tr.truePoses);
	EXPECT_LT(err.maxXY, 0.10) << "worst at scan " << err.worstIndex;
}
