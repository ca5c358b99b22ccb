/* --merge's pure parts (MergeMaps.h): the keyframe replay's entries, and the re-hung
 * trajectory (each pose takes the move of its keyframe nearest in time). */
#include "MergeMaps.h"

#include <gtest/gtest.h>
#include <lrgc/common/se2.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>

#include <cmath>

using lrgc::TStampedPose;
using lrgc::TTrajectory;
using mrpt::math::TPose2D;

namespace
{
TStampedPose at(double t, double x, double y, double phi)
{
	return {mrpt::Clock::fromDouble(t), TPose2D(x, y, phi)};
}

void expectNear(const TPose2D& a, const TPose2D& b)
{
	EXPECT_NEAR(a.x, b.x, 1e-9);
	EXPECT_NEAR(a.y, b.y, 1e-9);
	EXPECT_NEAR(mrpt::math::wrapToPi(a.phi - b.phi), 0.0, 1e-9);
}

// A saved map of two keyframes, each a frame with one scan stamped 100 + k s, at (k, 0, 0.1 k).
lrgc::apps::TSavedMap twoKeyframes()
{
	lrgc::apps::TSavedMap map;
	map.path = "two.simplemap";
	for (int k = 0; k < 2; ++k)
	{
		auto scan = mrpt::obs::CObservation2DRangeScan::Create();
		scan->timestamp = mrpt::Clock::fromDouble(100.0 + k);
		auto sf = mrpt::obs::CSensoryFrame::Create();
		sf->insert(scan);
		auto pose = mrpt::poses::CPose3DPDFGaussian::Create();
		pose->mean = mrpt::poses::CPose3D(k, 0, 0, 0.1 * k, 0, 0);
		map.keyframes.insert(pose, sf);
	}
	return map;
}
}  // namespace

TEST(KeyframeReplay, givesEachKeyframesPoseAsOdometryThenItsFrame)
{
	const lrgc::apps::TSavedMap map = twoKeyframes();
	lrgc::apps::CKeyframeReplay replay(map);
	for (int k = 0; k < 2; ++k)
	{
		auto odo = replay.next();
		ASSERT_TRUE(odo && odo->observation);
		const auto o =
			std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(odo->observation);
		ASSERT_TRUE(o);
		expectNear(o->odometry.asTPose(), TPose2D(k, 0, 0.1 * k));
		EXPECT_EQ(mrpt::Clock::toDouble(o->timestamp), 100.0 + k);
		auto frame = replay.next();
		ASSERT_TRUE(frame && frame->observations);
		EXPECT_EQ(frame->observations->size(), 1u);
		EXPECT_EQ(frame->where, "two.simplemap: keyframe " + std::to_string(k));
	}
	EXPECT_FALSE(replay.next());
	EXPECT_EQ(replay.fractionRead(), 1.0);
	ASSERT_EQ(replay.keyframePoses().size(), 2u);
	expectNear(replay.keyframePoses()[1].robotInMap, TPose2D(1, 0, 0.1));
}

TEST(RehangTrajectory, eachPoseTakesTheMoveOfItsNearestKeyframe)
{
	// Keyframe 0 moved by (5, 2, 90 deg), keyframe 1 (t = 10) by (-1, 0, 0).
	const TTrajectory before{at(0, 0, 0, 0), at(10, 1, 0, 0)};
	const TPose2D move0(5, 2, M_PI / 2), move1(-1, 0, 0);
	const TTrajectory after{{before[0].timestamp, lrgc::compose(move0, before[0].robotInMap)},
							{before[1].timestamp, lrgc::compose(move1, before[1].robotInMap)}};
	const TTrajectory dense{at(0, 0, 0, 0), at(4, 0.4, 0.1, 0.2), at(6, 0.6, 0, 0),
							at(12, 1.2, 0, 0)};
	const TTrajectory out = lrgc::apps::rehangTrajectory(dense, before, after);
	ASSERT_EQ(out.size(), dense.size());
	expectNear(out[0].robotInMap, lrgc::compose(move0, dense[0].robotInMap));
	expectNear(out[1].robotInMap, lrgc::compose(move0, dense[1].robotInMap));  // nearer t = 0
	expectNear(out[2].robotInMap, lrgc::compose(move1, dense[2].robotInMap));  // nearer t = 10
	expectNear(out[3].robotInMap, lrgc::compose(move1, dense[3].robotInMap));  // past the last
	EXPECT_EQ(out[1].timestamp, dense[1].timestamp);
}

TEST(RehangTrajectory, keyframesNotMappedAreSkippedAndNoScansGiveTheKeyframes)
{
	const TTrajectory before{at(0, 0, 0, 0), at(10, 1, 0, 0)};
	const TTrajectory after{at(10, 3, 0, 0)};  // keyframe 0 was not mapped in the replay
	const TTrajectory out = lrgc::apps::rehangTrajectory({at(1, 0.1, 0, 0)}, before, after);
	ASSERT_EQ(out.size(), 1u);
	expectNear(out[0].robotInMap, TPose2D(2.1, 0, 0));  // keyframe 1's move: (+2, 0, 0)
	const TTrajectory none = lrgc::apps::rehangTrajectory({}, before, after);
	ASSERT_EQ(none.size(), 1u);
	expectNear(none[0].robotInMap, TPose2D(3, 0, 0));
}
