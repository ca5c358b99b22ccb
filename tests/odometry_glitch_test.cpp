/* Odometry glitches through the whole map builder: the benchmark logs have single odometry
 * steps that turn 60-85 deg wrongly. A synthetic run in the room world is fed to
 * CMetricMapBuilderLRGC as lone CObservationOdometry + CObservation2DRangeScan; one
 * odometry increment gets a wrong turn. The local registration must notice (the match from
 * the odometry prior fails, the step turns more than glitch_min_turn: wide rotational
 * search, odometry link down-weighted) and the trajectory must stay on the ground truth.
 * A run without the glitch is the reference, and a run with the wide search switched off
 * shows that the glitch does break the map when nothing handles it. */
#include <gtest/gtest.h>
#include <lrgc/common/se2.h>

#include "synthetic_run.h"

using namespace lrgc::test;
using lrgc::CMetricMapBuilderLRGC;
using lrgc::TLRGCParams;

namespace
{
constexpr double kTolXY = 0.05;               // [m] every scan of the trajectory
constexpr double kTolPhi = 1.0 * M_PI / 180;  // [rad]

// 188 steps of 0.1 m along a loop through the room, turning in place by 20 deg steps.
TTrajectory roomLoop()
{
	return makeTrajectory(
		{{1.5, 3.5}, {5.5, 3.5}, {5.5, 5.8}, {1.2, 5.8}, {1.2, 3.0}, {4.5, 3.0}}, 0.1,
		TOdometryNoise{}, 11);
}

const CSyntheticWorld& roomWorld()
{
	static const CSyntheticWorld w = makeRoomWorld(5, 4);
	return w;
}

struct TGlitch
{
	size_t step;      //!< odometry increment step -> step + 1 is wrong
	double turn_deg;  //!< wrong extra turn
};

TTrajectory withGlitch(const TGlitch& g)
{
	TTrajectory tr = roomLoop();
	tr.odometryIncrements.at(g.step).phi += g.turn_deg * M_PI / 180;
	rebuildOdometryPoses(tr);
	return tr;
}

TTrajectoryError run(CMetricMapBuilderLRGC& builder, const TTrajectory& tr)
{
	feedBuilder(builder, roomWorld(), tr, TSyntheticRunOptions{});
	EXPECT_EQ(builder.stats().scans, tr.truePoses.size());
	EXPECT_EQ(builder.stats().skippedScans, 0U);
	return trajectoryError(builder.trajectory(), tr.truePoses);
}
}  // namespace

TEST(OdometryGlitch, scenarioIsCollisionFreeAndTheCleanRunIsOnTruth)
{
	const TTrajectory tr = roomLoop();
	ASSERT_GT(minClearance(roomWorld(), tr.truePoses), 0.5);
	CMetricMapBuilderLRGC builder;
	const auto e = run(builder, tr);
	EXPECT_LT(e.maxXY, kTolXY);
	EXPECT_LT(e.maxPhi, kTolPhi);
	// No step of clean odometry is rejected or treated as a glitch.
	EXPECT_EQ(builder.stats().odometryRejected, 0U);
	EXPECT_EQ(builder.stats().glitchesRecovered, 0U);
	EXPECT_EQ(builder.stats().unmatchedScans, 0U);
	// Dead reckoning alone is metres off: the scans carry the estimate.
	EXPECT_GT(trajectoryError(tr.odometryPoses, tr.truePoses).maxXY, 1.0);
}

class OdometryGlitchAt : public ::testing::TestWithParam<TGlitch>
{
};

TEST_P(OdometryGlitchAt, isRecoveredAndTheTrajectoryStaysOnTruth)
{
	const TTrajectory tr = withGlitch(GetParam());
	CMetricMapBuilderLRGC builder;
	const auto e = run(builder, tr);
	EXPECT_LT(e.maxXY, kTolXY) << "worst scan " << e.worstIndex;
	EXPECT_LT(e.maxPhi, kTolPhi);
	// The mechanism (LocalRegistration.cpp): the odometry match fails, the step is suspect,
	// the wide search finds the pose, the prior is rejected -> glitchesRecovered.
	EXPECT_GE(builder.stats().glitchesRecovered, 1U);
	EXPECT_GE(builder.stats().odometryRejected, 1U);
	// ... and only that one step is affected.
	EXPECT_LE(builder.stats().odometryRejected, 2U);

	// Same run, same glitch, wide rotational search switched off: the map breaks.
	TLRGCParams narrow;
	narrow.local.wide_search_angle = 0;
	CMetricMapBuilderLRGC unprotected(narrow);
	const auto bad = run(unprotected, tr);
	EXPECT_GT(bad.maxXY, 0.5) << "the glitch should matter without the wide search";
	EXPECT_EQ(unprotected.stats().glitchesRecovered, 0U);
}

// Glitches while driving straight (step 20, 100) and at the start of a turn in place (43).
INSTANTIATE_TEST_SUITE_P(SyntheticRoom, OdometryGlitchAt,
						 ::testing::Values(TGlitch{20, 60}, TGlitch{43, -70}, TGlitch{100, 85},
										   TGlitch{20, -85}),
						 [](const ::testing::TestParamInfo<TGlitch>& p)
						 {
							 const auto& g = p.param;
							 return "step" + std::to_string(g.step) +
									(g.turn_deg < 0 ? "_minus" : "_plus") +
									std::to_string(int(std::abs(g.turn_deg))) + "deg";
						 });
