/* Keyframe reuse (issue 12, CKeyframeReuse): a robot that keeps driving the same building
 * must not grow its graph with the time driven. The ring of loop_closing_test.cpp (20 m x
 * 14 m of 2 m corridors, a 6 m laser, wheels slipping 9 % on the north corridor so the map
 * drifts and the loop must be closed first), with 24 boxes along its walls so that most
 * places constrain a scan match in every direction, is driven three times. With the defaults
 * the second and third turns add few keyframes: the scans hang from the first turn's keyframes,
 * the loop is closed by true links only, and the trajectory is as near the truth as without
 * reuse. With [KeyframeReuse] enabled = false the same observations add a keyframe every
 * 0.3 m on every turn (the test's own control: the counts it asserts are not a given).
 */
#include <gtest/gtest.h>
#include <lrgc/common/se2.h>

#include "synthetic_run.h"

using namespace lrgc::test;
using lrgc::CMetricMapBuilderLRGC;
using lrgc::TLRGCParams;

namespace
{
constexpr double W = 20, H = 14;  // [m] ring size

struct TRun
{
	TTrajectoryError error;
	lrgc::TMapBuilderStats stats;
	TLoopLinkAudit links;
	size_t firstTurnKeyframes = 0;  //!< made while driving the first turn
	size_t laterKeyframes = 0;      //!< made on the second and third turns
};

TRun runThreeTurns(bool reuse)
{
	const auto world = makeRingCorridorWorld(W, H, 2.0, 5, 24);
	const std::vector<Eigen::Vector2d> turn = {{W - 1, 1}, {W - 1, H - 1}, {1, H - 1}, {1, 1}};
	std::vector<Eigen::Vector2d> waypoints = {{4, 1}};
	for (int k = 0; k < 3; ++k) waypoints.insert(waypoints.end(), turn.begin(), turn.end());
	waypoints.push_back({4, 1});
	TTrajectory tr = makeTrajectory(waypoints, 0.2, TOdometryNoise{}, 11);
	for (size_t k = 0; k < tr.odometryIncrements.size(); ++k)
		if (tr.truePoses[k].y > H - 2)
		{
			tr.odometryIncrements[k].x *= 1.09;
			tr.odometryIncrements[k].y *= 1.09;
		}
	rebuildOdometryPoses(tr);
	// The first turn ends where the robot is back at (1, 1) for the first time.
	size_t firstTurnEnd = 0;
	for (size_t k = tr.truePoses.size() / 6; k < tr.truePoses.size(); ++k)
		if (std::hypot(tr.truePoses[k].x - 1, tr.truePoses[k].y - 1) < 0.3)
		{
			firstTurnEnd = k;
			break;
		}
	EXPECT_GT(firstTurnEnd, 0U);

	TSyntheticRunOptions opt;
	opt.laser.maxRange = 6;
	TLRGCParams p;
	p.reuse.enabled = reuse;
	CMetricMapBuilderLRGC builder(p);
	feedBuilder(builder, world, tr, opt);
	TRun r{trajectoryError(builder.trajectory(), tr.truePoses), builder.stats(),
		   auditLoopLinks(builder, tr.truePoses, 0.3, 5 * M_PI / 180)};
	for (const auto& kf : builder.keyframes())
		++(kf.scanIndex <= firstTurnEnd ? r.firstTurnKeyframes : r.laterKeyframes);
	return r;
}
}  // namespace

TEST(KeyframeReuse, drivingTheRingAgainAddsFewKeyframes)
{
	const TRun without = runThreeTurns(false);
	const TRun with = runThreeTurns(true);
	RecordProperty("keyframes_without", std::to_string(without.stats.keyframes));
	RecordProperty("keyframes_with", std::to_string(with.stats.keyframes));
	RecordProperty("rms_without_mm", std::to_string(1000 * without.error.rmsXY));
	RecordProperty("rms_with_mm", std::to_string(1000 * with.error.rmsXY));
	// Without reuse every turn adds as many keyframes as the first.
	EXPECT_GT(without.laterKeyframes, 1.5 * without.firstTurnKeyframes);
	EXPECT_EQ(without.stats.keyframesReused, 0U);
	// With it, the second and third turns together add about a third of the first's (measured
	// 44 against 154; without reuse 344): where a match leaves the corridor's axis free, a
	// new keyframe and a loop search are made instead.
	EXPECT_LT(with.laterKeyframes, 0.35 * with.firstTurnKeyframes)
		<< with.laterKeyframes << " keyframes after a first turn of "
		<< with.firstTurnKeyframes;
	EXPECT_GT(with.stats.keyframesReused, with.firstTurnKeyframes);
	// The loop is still closed, by true links only, and the map is as good.
	EXPECT_GT(with.stats.loopClosures, 0U);
	EXPECT_EQ(with.links.enabledFalse, 0U) << with.links.firstEnabledFalse;
	EXPECT_LT(with.error.rmsXY, 1.2 * without.error.rmsXY + 0.005);  // measured 9.5 vs 15 mm
	EXPECT_LT(with.error.maxXY, 0.5);
}
