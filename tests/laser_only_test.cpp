/* Laser only: no odometry observation at all, so every prior comes from the builder's
 * constant-velocity model (CMotionPredictor). Synthetic runs fed to CMetricMapBuilderLRGC
 * as lone CObservation2DRangeScan at 5 Hz must still track the ground truth, including the
 * turns in place (20 deg per scan, the constant-velocity prior is then 20 deg and 0.1-0.2 m
 * off at the turn's onset). */
#include <gtest/gtest.h>
#include <lrgc/common/se2.h>

#include "synthetic_run.h"

using namespace lrgc::test;
using lrgc::CMetricMapBuilderLRGC;

namespace
{
void expectNoOdometryWasUsed(const CMetricMapBuilderLRGC& b)
{
	// Without odometry no odometry step can be judged a glitch or rejected.
	EXPECT_EQ(b.stats().glitchesRecovered, 0U);
	EXPECT_EQ(b.stats().ignoredObservations, 0U);
}
}  // namespace

TEST(LaserOnly, constantVelocityTracksALoopInARoom)
{
	const auto world = makeRoomWorld(5, 4);
	// 0.1 m per scan (0.5 m/s) and turns in place of 20 deg per scan (100 deg/s).
	const auto tr =
		makeTrajectory({{1.5, 3.5}, {5.5, 3.5}, {5.5, 5.8}, {1.2, 5.8}, {1.2, 3.0}, {4.5, 3.0}},
					   0.1, TOdometryNoise{}, 11);
	TSyntheticRunOptions opt;
	opt.odometry = false;
	CMetricMapBuilderLRGC builder;
	feedBuilder(builder, world, tr, opt);
	ASSERT_EQ(builder.stats().scans, tr.truePoses.size());
	const auto e = trajectoryError(builder.trajectory(), tr.truePoses);
	EXPECT_LT(e.maxXY, 0.05) << "worst scan " << e.worstIndex;
	EXPECT_LT(e.maxPhi, 1.0 * M_PI / 180);
	EXPECT_EQ(builder.stats().unmatchedScans, 0U);
	expectNoOdometryWasUsed(builder);
	// The run covers the loop: keyframes every 0.3 m or 15 deg.
	EXPECT_GT(builder.stats().keyframes, 50U);
}

TEST(LaserOnly, constantVelocityTracksARingCorridorWithSparseFeatures)
{
	// A 20 m x 14 m ring of 2 m wide corridors, 30 boxes along its walls, a 6 m laser: along
	// a corridor the motion is observable only near boxes and corners, elsewhere the
	// constant-velocity model carries it. One and a quarter turns of the ring (826 scans).
	const double W = 20, H = 14;
	const auto world = makeRingCorridorWorld(W, H, 2.0, 5, 30);
	const auto tr = makeTrajectory(
		{{4, 1}, {W - 1, 1}, {W - 1, H - 1}, {1, H - 1}, {1, 1}, {W - 1, 1}, {W - 1, 6}}, 0.1,
		TOdometryNoise{}, 11);
	ASSERT_GT(minClearance(world, tr.truePoses), 0.5);
	TSyntheticRunOptions opt;
	opt.odometry = false;
	opt.laser.maxRange = 6;
	CMetricMapBuilderLRGC builder;
	feedBuilder(builder, world, tr, opt);
	ASSERT_EQ(builder.stats().scans, tr.truePoses.size());
	const auto e = trajectoryError(builder.trajectory(), tr.truePoses);
	EXPECT_LT(e.maxXY, 0.10) << "worst scan " << e.worstIndex;
	EXPECT_LT(e.rmsXY, 0.05);
	EXPECT_LT(e.maxPhi, 1.0 * M_PI / 180);
	expectNoOdometryWasUsed(builder);
}

// Disabled: a known, open limitation, kept as its reproducer (run it with
// lrgc_e2e_tests --gtest_also_run_disabled_tests --gtest_filter='LaserOnly.DISABLED_*').
// Without odometry a failed match keeps the constant-velocity prior (LocalRegistration.cpp
// registerScan), which runs away by 20 deg per scan at a turn's onset, and the wide search only
// runs for a suspect step (turn > glitch_min_turn or a pause in the scans), so the run loses
// its heading (measured before: 28.5 m, 89.6 deg). A wide search at every failure fixes this
// run but made ACES laser-only worse (0.46 -> 3.2 m mean relation error).
TEST(LaserOnly, DISABLED_constantVelocityFollowsTurnOnsetsAtOneMetrePerSecond)
{
	// The same ring, 60 boxes, 0.2 m per scan (1 m/s at 5 Hz) then turning in place at
	// 100 deg/s: at each corner the constant-velocity prior is 0.2 m and 20 deg off and the
	// corridor's right angles offer 90 deg-rotated alignments.
	const double W = 20, H = 14;
	const auto world = makeRingCorridorWorld(W, H, 2.0, 5, 60);
	const auto tr = makeTrajectory(
		{{4, 1}, {W - 1, 1}, {W - 1, H - 1}, {1, H - 1}, {1, 1}, {W - 1, 1}, {W - 1, 6}}, 0.2,
		TOdometryNoise{}, 11);
	ASSERT_GT(minClearance(world, tr.truePoses), 0.5);
	TSyntheticRunOptions opt;
	opt.odometry = false;
	opt.laser.maxRange = 6;
	CMetricMapBuilderLRGC builder;
	feedBuilder(builder, world, tr, opt);
	ASSERT_EQ(builder.stats().scans, tr.truePoses.size());
	const auto e = trajectoryError(builder.trajectory(), tr.truePoses);
	EXPECT_LT(e.maxXY, 0.15) << "worst scan " << e.worstIndex;
	EXPECT_LT(e.maxPhi, 2.0 * M_PI / 180);
}
