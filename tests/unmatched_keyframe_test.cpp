/* An unmatched keyframe re-matched at the end of the run (issue 28 item 4; KeyframeRematch.h).
 * ACES made sparse has a keyframe 50-59 deg off its neighbours: after a pause the robot turned
 * -104 deg between two scans while its odometry read -48, and the scan saw what the window's
 * keyframes, all facing the other way, had not; it matched nothing and kept the odometry's
 * pose, which only odometry links hold. The same here, in the room world: the robot drives
 * along +x, turns 175 deg in place in one step while the odometry of that one pose reads 80
 * deg more (the next pose's right again, as a glitch in a sparse log's odometry), and drives
 * back: the wide search online (+- 90 deg around the odometry) finds no evidence against a
 * window that saw only the other half of the room, and the scan keeps the odometry's pose.
 * After the run the keyframes that came later see the place from the new side: the wide search
 * finds the keyframe's heading against them, with its evidence, and the final optimisation
 * places it; without the re-match it stays tens of degrees off. */
#include <gtest/gtest.h>
#include <lrgc/common/se2.h>

#include "synthetic_run.h"

#include <mrpt/core/bits_math.h>
#include <mrpt/math/wrap2pi.h>

using namespace lrgc::test;
using lrgc::CMetricMapBuilderLRGC;

namespace
{
/** 0.1 m steps along +x, one step turning 175 deg in place at (6, 4), then 2 m back. */
TTrajectory turnInPlace(size_t& turnStep)
{
	const double turn = mrpt::DEG2RAD(175.0);
	TTrajectory tr =
		makeTrajectory({{2.5, 4}, {6, 4}, {6 + 2 * std::cos(turn), 4 + 2 * std::sin(turn)}},
					   0.1, TOdometryNoise{}, 11, mrpt::DEG2RAD(170.0));
	for (turnStep = 1; turnStep < tr.truePoses.size(); ++turnStep)
		if (std::abs(mrpt::math::wrapToPi(tr.truePoses[turnStep].phi -
										  tr.truePoses[turnStep - 1].phi)) > 1)
			break;
	// The odometry of the pose after the turn reads 80 deg more turn; the next one is right.
	tr.odometryPoses.at(turnStep).phi += mrpt::DEG2RAD(80.0);
	for (size_t k = 0; k + 1 < tr.truePoses.size(); ++k)
		tr.odometryIncrements[k] = lrgc::between(tr.odometryPoses[k], tr.odometryPoses[k + 1]);
	return tr;
}
}  // namespace

TEST(UnmatchedKeyframe, isRematchedAgainstTheMapAtTheEndOfTheRun)
{
	size_t turn = 0;  // the scan after the turn
	const TTrajectory tr = turnInPlace(turn);
	const CSyntheticWorld world = makeRoomWorld(5, 4);
	ASSERT_LT(turn, tr.truePoses.size());
	ASSERT_GT(minClearance(world, tr.truePoses), 1.0);
	CMetricMapBuilderLRGC builder;
	feedBuilder(builder, world, tr, TSyntheticRunOptions{});
	const auto traj = builder.trajectory();
	ASSERT_EQ(traj.size(), tr.truePoses.size());
	// The scan after the turn, against its true pose and its neighbours' headings (the map's
	// frame is the first true pose's).
	const auto offBy = [&](size_t k)
	{ return std::abs(mrpt::math::wrapToPi(traj[k].robotInMap.phi - tr.truePoses[k].phi)); };
	EXPECT_GE(builder.stats().unmatchedScans, 1U);
	EXPECT_EQ(builder.stats().keyframesRematched, 1U);
	EXPECT_LT(offBy(turn), mrpt::DEG2RAD(1.0)) << "scan " << turn;
	EXPECT_LT(offBy(turn - 1), mrpt::DEG2RAD(1.0));
	EXPECT_LT(offBy(turn + 1), mrpt::DEG2RAD(1.0));
	EXPECT_LT(trajectoryError(traj, tr.truePoses).maxXY, 0.05);
}
