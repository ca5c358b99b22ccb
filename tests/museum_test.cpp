/* A museum mapped from sparse scans (issue 28: "a museum hall, rows of similar alcoves, sparse
 * scans"): full SLAM in makeMuseumWorld, two 64 m galleries lined with identical niches around
 * a central block, with visitors walking. Three laps of the 136 m loop around the block, one
 * scan a metre (1 s apart) and turns in place of up to 80 deg between two scans; odometry
 * twice as noisy as the default model that turns 5 % and travels 4 % too much (the sparse
 * variants' scale errors, bench/make-sparse-log); a 30 m SICK (longRangeSick), so that from a
 * gallery's end its far end is out of reach and every niche looks like the next.
 *
 * Figures, from exact ground truth, as bench/glass_stress world=museum prints them:
 *  - relations under 10 s apart off by more than 2 deg (local registration's heading tail);
 *  - the mean error of long relations (every tenth scan to every tenth at least 60 s later):
 *    what a bent gallery or a wrong closure shows;
 *  - loop recall over the revisited 10 m places and false closures (synthetic_eval.h).
 */
#include <gtest/gtest.h>

#include <cstdio>

#include "synthetic_eval.h"

using namespace lrgc::test;
using lrgc::CMetricMapBuilderLRGC;

namespace
{
constexpr double kPeriod = 1.0;  // [s] between scans, 1 m apart

/** The run's harshness: metres between scans, the laser's range [m], visitors. */
struct TMuseumVariant
{
	double step_m = 1.0;
	double range_m = 30;
	int visitors = 15;
};

TTrajectory threeLaps(uint32_t seed, double step_m)
{
	const std::vector<Eigen::Vector2d> lap{{58, 6}, {58, 22}, {6, 22}, {6, 6}};
	std::vector<Eigen::Vector2d> wp{{14, 6}};
	for (int i = 0; i < 3; ++i) wp.insert(wp.end(), lap.begin(), lap.end());
	wp.emplace_back(42, 6);
	TOdometryNoise noise;
	noise.a1 *= 2, noise.a2 *= 2, noise.a3 *= 2, noise.a4 *= 2;
	TTrajectory tr = makeTrajectory(wp, step_m, noise, seed, mrpt::DEG2RAD(80.0));
	scaleOdometry(tr, 1.05, 1.04);
	return tr;
}

struct TMuseumRun
{
	lrgc::apps::eval::TRelationEvaluation shortRel, longRel;
	lrgc::apps::eval::TLoopRecall recall;
	double worst_m = 0;  //!< the map's worst position error from the first pose [m]
};

/** World seed `seed`, trajectory seed 60 + seed, visitors seeded 200 + seed, the defaults
 * but for loop closing (bench/glass_stress world=museum with the same seed and variant). */
TMuseumRun runMuseum(uint32_t seed, bool loopClosing, const TMuseumVariant& v = {})
{
	const CSyntheticWorld world = makeMuseumWorld(seed);
	const TTrajectory tr = threeLaps(60 + seed, v.step_m);
	EXPECT_GT(minClearance(world, tr.truePoses), 3.0);
	const CCrowd visitors(world.bounds(), v.visitors, 200 + seed);
	TSyntheticRunOptions opt = longRangeSick(kPeriod, v.range_m, 0.3, seed);
	opt.crowd = &visitors;
	lrgc::TLRGCParams p;
	p.builder.loop_closing = loopClosing;
	CMetricMapBuilderLRGC builder(p);
	builder.setMinLoggingLevel(mrpt::system::LVL_ERROR);
	feedBuilder(builder, world, tr, opt);

	const auto& est = builder.trajectory();
	TMuseumRun r{evaluateOnTruth(est, truthRelations(tr.truePoses, kPeriod, false)),
				 evaluateOnTruth(est, truthRelations(tr.truePoses, kPeriod, true)),
				 truthLoopRecall(builder, tr.truePoses, kPeriod),
				 trajectoryError(est, tr.truePoses).maxXY};
	std::printf(
		"[ museum ] seed %u%s: %zu scans (%zu unmatched), %zu keyframes; relations < 10 s: "
		"%zu over 2 deg of %zu; long relations %.3f m mean (max %.2f); loop recall %zu / %zu "
		"places, %zu false closures; worst pose %.2f m from the first\n",
		seed, loopClosing ? "" : " (local registration alone)", builder.stats().scans,
		builder.stats().unmatchedScans, builder.stats().keyframes, r.shortRel.shortOver2deg,
		r.shortRel.shortCount, r.longRel.trans_m.mean, r.longRel.trans_m.max, r.recall.closed,
		r.recall.places.size(), r.recall.falseClosures, r.worst_m);
	return r;
}
}  // namespace

TEST(MuseumSparse, galleriesStayStraightAndTheirRevisitsClose)
{
	for (const uint32_t seed : {1u, 2u})
	{
		const TMuseumRun r = runMuseum(seed, true);
		// Issue 28's bars (under 1 % over 2 deg, recall >= 90 %, no false closure) and a bent
		// gallery's: main at 6e021f6 keeps the long relations at 0.017-0.031 m on seeds 1-8
		// (bench/glass_stress world=museum, doc/generalisation.md), the museum the issue
		// names is at 0.127 m against a bar of 0.10 m.
		EXPECT_GT(r.recall.places.size(), 10U) << "laps 2 and 3 must revisit lap 1";
		EXPECT_EQ(r.recall.falseClosures, 0U) << lrgc::apps::eval::recallReport(r.recall);
		EXPECT_GE(r.recall.recall(), 0.9) << "seed " << seed;
		EXPECT_LT(r.shortRel.shortOver2degShare(), 0.01) << "seed " << seed;
		EXPECT_LT(r.longRel.trans_m.mean, 0.05) << "seed " << seed << ": a gallery bent";
	}
}

// Issue 28 item 3 (an unmatched scan never bends the map) where nothing repairs it later: seed
// 4's turn in place of 80 deg at (6, 6) among visitors. The odometry turns 10.9 deg too far;
// the plain match fails and the wide search's winner matches 43.8 % of the scan (rms 2.1 cm).
// With [ScanMatcher] wide_min_inlier_fraction at 0.45 (until session 64) it was refused, the
// odometry's turn stood and the map after it turned with it: long relations 3.07 m, worst scan
// 10.4 m and 11.1 deg off. At 0.40 it is taken: 0.038 m, worst scan 0.09 m and 0.2 deg.
TEST(MuseumSparse, aTurnInPlaceAmongVisitorsDoesNotBendLocalRegistration)
{
	const TMuseumRun r = runMuseum(4, false);
	EXPECT_LT(r.shortRel.shortOver2degShare(), 0.01);
	EXPECT_LT(r.longRel.trans_m.mean, 0.05) << "the map turned at a corner";
}

// Sparse steps among a crowd ([LocalRegistration] crowd_min_run_m): 1.5 m between scans, a
// 20 m laser, 25 visitors. Right plain matches were refused because visitors stood where the
// window's scans saw through (42-58 % of a scan's points by the strict count); the loose prior
// (a heading std of 4-5 deg a step) stood and the map bent: long relations 14.2 m (seed 4) and
// 3.50 m (seed 5) without the rule, 0.018 and 0.021 m with it (doc/generalisation.md).
TEST(MuseumSparse, aCrowdAmongSparseStepsDoesNotBendTheGalleries)
{
	for (const uint32_t seed : {4u, 5u})
	{
		const TMuseumRun r = runMuseum(seed, true, {1.5, 20, 25});
		EXPECT_EQ(r.recall.falseClosures, 0U) << lrgc::apps::eval::recallReport(r.recall);
		EXPECT_GE(r.recall.recall(), 0.9) << "seed " << seed;
		EXPECT_LT(r.shortRel.shortOver2degShare(), 0.01) << "seed " << seed;
		EXPECT_LT(r.longRel.trans_m.mean, 0.05) << "seed " << seed << ": a gallery bent";
	}
}

// The heading clear, the place not (CScanMatcher::matchWide's sharedHeading): the harsh
// variant's seed 8, scan 285, heading south in the west end hall where the odometry turns
// 12.5 deg and the truth goes straight. The plain match from the prior fails; the retry over
// +-15 deg finds the true heading, but a rival at the same heading and another position (a
// niche further along, or visitors) explains nearly as much (0.525 against 0.602), so
// matchWide refused and the prior stood: long relations 1.19 m, worst scan 6.9 m off. Matched
// again from the prior's position at that heading: 0.060 m, worst 0.49 m.
TEST(MuseumSparse, aRetryWhoseRivalsShareTheHeadingKeepsTheHeading)
{
	const TMuseumRun r = runMuseum(8, true, {1.5, 20, 25});
	EXPECT_EQ(r.recall.falseClosures, 0U) << lrgc::apps::eval::recallReport(r.recall);
	EXPECT_GE(r.recall.recall(), 0.9);
	EXPECT_LT(r.shortRel.shortOver2degShare(), 0.01);
	EXPECT_LT(r.longRel.trans_m.mean, 0.1) << "the gallery turned at the west end hall";
}

// Issue 28 item 4, the first keyframes move with the rest: the harsh variant's seed 1, whose
// first step (scan 1 against scan 0 alone, the only keyframe of the window then) matched 8.5
// deg off, where the odometry read 7.4 deg off too. The later laps' closures link keyframes 1
// and after, never 0, so the whole map stood turned about the start: long relations 0.054 m,
// but three 10 s relations from scan 0 over 5 deg and the map 6.9 m off its first pose 45 m
// away. Re-matched at the end of the run against the map around it (CKeyframeRematcher),
// keyframe 0 turns, and the map with it: 0.021 m, the worst pose 0.04 m off.
TEST(MuseumSparse, theFirstKeyframeIsPlacedByTheMapAroundIt)
{
	const TMuseumRun r = runMuseum(1, true, {1.5, 20, 25});
	EXPECT_EQ(r.recall.falseClosures, 0U) << lrgc::apps::eval::recallReport(r.recall);
	EXPECT_EQ(r.shortRel.shortOver2deg, 0U) << "relations from the first scan";
	EXPECT_LT(r.worst_m, 0.3) << "the map turned about its first pose";
}
