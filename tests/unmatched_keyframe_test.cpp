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

#include <algorithm>
#include <cmath>

using namespace lrgc::test;
using lrgc::CMetricMapBuilderLRGC;

namespace
{
/** 0.1 m steps along +x, one step turning `turnDeg` in place at (6, 4) (at most 170 deg in
 * one step, the rest in the next), then 2 m back; odometry noise seeded by `seed`. The
 * odometry of the pose after the turn reads `glitchDeg` more turn; the next one is right. */
TTrajectory turnInPlace(size_t& turnStep, double turnDeg = 175, double glitchDeg = 80,
						uint32_t seed = 11)
{
	const double turn = mrpt::DEG2RAD(turnDeg);
	TTrajectory tr =
		makeTrajectory({{2.5, 4}, {6, 4}, {6 + 2 * std::cos(turn), 4 + 2 * std::sin(turn)}},
					   0.1, TOdometryNoise{}, seed, mrpt::DEG2RAD(170.0));
	for (turnStep = 1; turnStep < tr.truePoses.size(); ++turnStep)
		if (std::abs(mrpt::math::wrapToPi(tr.truePoses[turnStep].phi -
										  tr.truePoses[turnStep - 1].phi)) > 1)
			break;
	tr.odometryPoses.at(turnStep).phi += mrpt::DEG2RAD(glitchDeg);
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

/* An unmatched scan never bends the map (issue 28 item 3): the same room and turn, with the
 * turn and the one-pose glitch varied. Before, 20 of 48 such runs (turns of 90, 135 and 175
 * deg; glitches of +40, +80, +120 and -80 deg; odometry seeds 11-14) broke online, every scan
 * after the turn ending 40-180 deg off, and 97 of 144 of a wider set (turns of 100-165 deg,
 * glitches of -120 to +100 deg or none, seeds 11-16); now 0 of 48 and 10 of 144 (a glitch that
 * makes the next step a "jump", a turn the jump test refuses whose scans match nothing: the
 * odometry's two readings then have no scan to decide between them). The variants below each
 * broke a different way:
 *  - a turn of 135 or 150 deg in one 0.2 s step (+40 deg read or none) exceeds the odometry
 *    jump test: that scan took the constant-velocity prior, matched nothing, and the next
 *    scan's odometry, composed onto it, put it 135-150 deg off (MotionPredictor.h: the
 *    alternative);
 *  - 175 deg read +120: the wide search placed the glitched scan right, and the next step's
 *    odometry (-115 deg, undoing the glitch) from there sent the next scan's wide search to a
 *    rotated twin of the room (the alternative);
 *  - 175 deg read +80: the glitched scan, unmatched, became a keyframe 80 deg off, and the
 *    next scan's wide search won on that keyframe's own points (LocalRegistration.h: a wide
 *    search's winner must hold against the keyframes a match placed);
 *  - 150 deg read -40: two unmatched keyframes in a row, the second on the right odometry,
 *    and their pairwise match pulled the second into the first's wrong frame
 *    (LocalRegistration.h: a disputed keyframe).
 * Every scan after the glitched one must end within 10 deg and 0.5 m of the truth: a turn of
 * 150 deg carries some 6 deg of the odometry's own error (a1 = 0.05 rad/rad) where no scan
 * matched the map after it; loop closing is what repairs that. About 0.6 s. */
TEST(UnmatchedKeyframe, aOnePoseOdometryGlitchNeverBendsTheMap)
{
	struct TVariant
	{
		double turnDeg, glitchDeg;
		uint32_t seed;
	};
	const CSyntheticWorld world = makeRoomWorld(5, 4);
	for (const TVariant& v :
		 {TVariant{135, 40, 11}, TVariant{150, 0, 11}, TVariant{175, 120, 11},
		  TVariant{175, 80, 12}, TVariant{150, -40, 12}})
	{
		SCOPED_TRACE(testing::Message() << "turn " << v.turnDeg << " deg, glitch "
										<< v.glitchDeg << " deg, seed " << v.seed);
		size_t turn = 0;
		const TTrajectory tr = turnInPlace(turn, v.turnDeg, v.glitchDeg, v.seed);
		ASSERT_LT(turn + 1, tr.truePoses.size());
		CMetricMapBuilderLRGC builder;
		feedBuilder(builder, world, tr, TSyntheticRunOptions{});
		const auto traj = builder.trajectory();
		ASSERT_EQ(traj.size(), tr.truePoses.size());
		double worstPhi = 0, worstXY = 0;
		for (size_t k = turn + 1; k < traj.size(); ++k)
		{
			const mrpt::math::TPose2D truth = lrgc::between(tr.truePoses[0], tr.truePoses[k]);
			const mrpt::math::TPose2D& est = traj[k].robotInMap;
			worstPhi = std::max(worstPhi, std::abs(mrpt::math::wrapToPi(est.phi - truth.phi)));
			worstXY = std::max(worstXY, std::hypot(est.x - truth.x, est.y - truth.y));
		}
		EXPECT_LT(worstPhi, mrpt::DEG2RAD(10.0));
		EXPECT_LT(worstXY, 0.5);
	}
}
