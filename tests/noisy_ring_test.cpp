/* A noisy laser in a world of the test simulator (issue 28 item 2): the ring of
 * loop_closing_test.cpp made larger (30 x 20 m, 5 m corridors, 12 boxes of 0.3 m along the
 * outer walls) seen by a 180 deg, 361-beam, 30 m laser with the range noise of MRPT's
 * range_030_bearing_015.rawlog, 0.30 m std. The odometry slips on the north corridor (9 % too
 * long there) and the robot drives one and a quarter turns, back past its start (562 scans,
 * 0.2 m apart). With the defaults the builder must read the laser's noise from the scans
 * (RangeDenoiser.h), register the scans, and close the loop with true links only.
 * Figures before and after: doc/generalisation.md, "A noisy laser". */
#include <gtest/gtest.h>
#include <lrgc/common/se2.h>
#include <lrgc_apps/eval/loop_recall.h>

#include <algorithm>
#include <cstdio>

#include "synthetic_run.h"

using namespace lrgc::test;
using lrgc::CMetricMapBuilderLRGC;
using lrgc::TLRGCParams;

namespace
{
constexpr double kNoisyRingW = 30, kNoisyRingH = 20;  // [m] the ring's outer walls
constexpr double kRingCorridor = 5;                   // [m] its corridors' width
constexpr double kSlip = 1.09;       // odometry translation / true, on the north corridor
constexpr double kRangeNoise = 0.3;  // [m] range_030_bearing_015.rawlog's
constexpr double kRingPeriod = 0.2;  // [s] between scans (TSyntheticRunOptions' default)

/** Seeds of a run: the boxes' places, the laser's noise, the odometry's noise. */
struct TRingSeeds
{
	uint32_t world, laser, odometry;
};

/** 1.25 laps along the corridors' centre lines, 0.2 m steps, the north corridor slipping. */
TTrajectory slippingNoisyRing(uint32_t seed)
{
	const double c = kRingCorridor / 2;
	TTrajectory tr = makeTrajectory({{6, c},
									 {kNoisyRingW - c, c},
									 {kNoisyRingW - c, kNoisyRingH - c},
									 {c, kNoisyRingH - c},
									 {c, c},
									 {kNoisyRingW - c, c},
									 {kNoisyRingW - c, 8}},
									0.2, TOdometryNoise{}, seed);
	for (size_t k = 0; k < tr.odometryIncrements.size(); ++k)
		if (tr.truePoses[k].y > kNoisyRingH - kRingCorridor)
		{
			tr.odometryIncrements[k].x *= kSlip;
			tr.odometryIncrements[k].y *= kSlip;
		}
	rebuildOdometryPoses(tr);
	return tr;
}

/** Loop recall over the revisited places by lrgc-eval --loops's definition
 * (lrgc_apps/eval/loop_recall.h), the truth exact. */
lrgc::apps::eval::TLoopRecall ringLoopRecall(const CMetricMapBuilderLRGC& builder,
											 const std::vector<mrpt::math::TPose2D>& truth)
{
	std::vector<lrgc::apps::eval::TRecallKeyframe> kfs;
	for (const auto& kf : builder.keyframes())
		kfs.push_back({kRingPeriod * double(kf.scanIndex), truth.at(kf.scanIndex)});
	return lrgc::apps::eval::evaluateLoopRecall(builder.graph(), kfs);
}
class NoisyRing : public ::testing::TestWithParam<TRingSeeds>
{
};
}  // namespace

TEST_P(NoisyRing, mapsAndClosesTheLoopWithRangeNoiseOf30cm)
{
	const TRingSeeds seeds = GetParam();
	const auto world =
		makeRingCorridorWorld(kNoisyRingW, kNoisyRingH, kRingCorridor, seeds.world, 12);
	const TTrajectory tr = slippingNoisyRing(seeds.odometry);
	EXPECT_GT(minClearance(world, tr.truePoses), 1.5);
	TSyntheticRunOptions opt;
	opt.scanPeriod = kRingPeriod;
	opt.laserSeed = seeds.laser;
	opt.laser.maxRange = 30;
	opt.laser.rangeNoiseStd = kRangeNoise;
	CMetricMapBuilderLRGC builder{TLRGCParams{}};
	feedBuilder(builder, world, tr, opt);
	const TTrajectoryError err = trajectoryError(builder.trajectory(), tr.truePoses);
	const TLoopLinkAudit links = auditLoopLinks(builder, tr.truePoses, 0.3, 5 * M_PI / 180);
	const auto recall = ringLoopRecall(builder, tr.truePoses);
	const auto& st = builder.stats();
	std::printf(
		"[ noisy ring ] %zu scans, %zu unmatched; position rms %.3f m, max %.3f m, final "
		"%.3f m; online closures %zu, links true %zu, false %zu (worst %.3f m); loop recall "
		"%zu / %zu places, %zu false closures\n",
		st.scans, st.unmatchedScans, err.rmsXY, err.maxXY, err.finalXY, st.loopClosures,
		links.enabledTrue, links.enabledFalse, links.worstEnabledXY, recall.closed,
		recall.places.size(), recall.falseClosures);
	EXPECT_EQ(st.scans, tr.truePoses.size());
	// Registered: 0-1 scans unmatched (353 for the first when the denoiser fitted its lines
	// through the points, whose walls then carved free space into each other), position rms
	// 0.072-0.104 m (0.631).
	EXPECT_LT(st.unmatchedScans, 10U);
	EXPECT_LT(err.rmsXY, 0.15);
	// The loop closed online (22-27 closures), by true links only: one joins the last lap to
	// the first (keyframes half the run apart), and the end, back on the start's corridor, is
	// near the truth.
	size_t longest = 0;
	for (const auto& [from, to] : links.enabledTrueLinks)
		longest = std::max(longest, to > from ? to - from : from - to);
	EXPECT_GT(longest, st.keyframes / 2);
	EXPECT_EQ(links.enabledFalse, 0U) << links.firstEnabledFalse;
	EXPECT_LT(err.finalXY, 0.3);
	EXPECT_GT(st.loopClosures, 0U);
	// Issue 28's bar: loop recall of 90 % or more (3 of 3 places), no false closure kept.
	EXPECT_GE(recall.recall(), 0.9) << lrgc::apps::eval::recallReport(recall);
	EXPECT_EQ(recall.falseClosures, 0U) << lrgc::apps::eval::recallReport(recall);
}

// The first seeds are loop_closing_test.cpp's; the others were picked blind. Over three more
// (5 2 11, 8 1 11, 8 2 12, 21 7 17, 34 9 3) the figures are alike: 0-2 unmatched, rms
// 0.059-0.120 m, 17-25 online closures, none false. 7 9 4 is the one of 20 further blind seeds
// that kept a false link (21 -> 233, 0.33 m off along the south corridor, stated std 0.03 m:
// chi2 118) before loop links of denoised scans got their floor (denoisedLoopLinkNoise,
// LinkNoise.h; now stated 0.10 m, chi2 12). Over those 20 seeds: 0-6 unmatched, rms
// 0.055-0.166 m (two above 0.15: 0.151, 0.166), 10-29 online closures, none false.
INSTANTIATE_TEST_SUITE_P(Seeds, NoisyRing,
						 ::testing::Values(TRingSeeds{5, 1, 11}, TRingSeeds{5, 3, 11},
										   TRingSeeds{13, 4, 13}, TRingSeeds{7, 9, 4}),
						 [](const ::testing::TestParamInfo<TRingSeeds>& p)
						 {
							 return "world" + std::to_string(p.param.world) + "laser" +
									std::to_string(p.param.laser) + "odometry" +
									std::to_string(p.param.odometry);
						 });
