/* Registration and loop closing through mixed returns (issue 28 item 2): full SLAM in a
 * 100 x 60 m building of glass and railings (makeGlassBuildingWorld) seen by an 80 m laser
 * of 181 beams over 180 deg whose start angle cycles through four values (as the long-range
 * SICK's ROBOTLASER lines), with the simulator's mixed returns: panes that let 80 % of the
 * beams through to the far side, railings whose posts return some beams and the far side the
 * others, mixed pixels wherever a beam's spot straddles an edge, max-range dropouts on far
 * and grazing surfaces. Scans are as sparse as that log's (one per 0.7 s, 0.4 m and up to
 * 34 deg apart) and the odometry twice as noisy as the default model. Two laps around the
 * courtyard block and on, so that every place of the second lap is a revisit.
 *
 * Figures, from exact ground truth:
 *  - the heading's tail of local registration: the share of relations under 10 s apart (about
 *    1, 5 and 9.8 s, from every fifth scan) off by more than 2 deg, by lrgc-eval's relation
 *    metric;
 *  - loop recall: the second visit's path cut into 10 m places (keyframes within 2 m of one
 *    at least 60 s older); a place is closed if one of its keyframes ends a true loop link
 *    kept in the final graph;
 *  - false closures: loop links kept in the final graph that disagree with the truth.
 * Issue 28's bars are asserted: under 1 % over 2 deg, recall >= 90 %, no false closure.
 */
#include <gtest/gtest.h>
#include <lrgc/common/se2.h>
#include <lrgc_apps/eval/loop_recall.h>
#include <lrgc_apps/eval/relation_metric.h>

#include <algorithm>
#include <cstdio>

#include "synthetic_eval.h"

using namespace lrgc::test;
using lrgc::CMetricMapBuilderLRGC;
using mrpt::math::TPose2D;

namespace
{
constexpr double kPeriod = 0.7;  // [s] between scans

TTrajectory twoLaps(uint32_t seed)
{
	const std::vector<Eigen::Vector2d> lap{{78, 12}, {78, 45}, {22, 45}, {22, 12}};
	std::vector<Eigen::Vector2d> wp{{22, 12}};
	for (int i = 0; i < 2; ++i) wp.insert(wp.end(), lap.begin(), lap.end());
	wp.emplace_back(50, 12);
	TOdometryNoise noise;
	noise.a1 *= 2, noise.a2 *= 2, noise.a3 *= 2, noise.a4 *= 2;
	return makeTrajectory(wp, 0.4, noise, seed, 0.6);
}
}  // namespace

TEST(GlassBuilding, registrationAndLoopsSurviveMixedReturns)
{
	const CSyntheticWorld world = makeGlassBuildingWorld(5, 0.2);
	const TTrajectory tr = twoLaps(61);
	ASSERT_GT(minClearance(world, tr.truePoses), 0.5);
	CMetricMapBuilderLRGC builder;
	builder.setMinLoggingLevel(mrpt::system::LVL_ERROR);
	feedBuilder(builder, world, tr, longRangeSick(kPeriod, 80, 0.15, 3));

	const auto rel =
		evaluateOnTruth(builder.trajectory(), truthRelations(tr.truePoses, kPeriod, false));
	const auto recall = truthLoopRecall(builder, tr.truePoses, kPeriod);
	const auto& st = builder.stats();
	const auto& ls = builder.loopCloserStats();
	std::printf(
		"[ glass building ] %zu scans (%zu unmatched), %zu keyframes; relations < 10 s: %zu, "
		"%zu over 2 deg (%.2f %%), %zu over 5 deg; loop recall %zu / %zu places; loop links "
		"kept %zu true, %zu false; %zu closures, %zu revisit links; searches %zu, rejected "
		"%zu by the filters, %zu by the match, %zu by the back-end, %zu shed\n",
		st.scans, st.unmatchedScans, st.keyframes, rel.shortCount, rel.shortOver2deg,
		100 * rel.shortOver2degShare(), rel.shortOver5deg, recall.closed, recall.places.size(),
		recall.loopLinks.size() - recall.falseClosures, recall.falseClosures, st.loopClosures,
		st.revisitLinks, ls.attempts, ls.rejectedByFilters, ls.rejectedByMatch,
		ls.rejectedByBackEnd, ls.searchesShed);
	std::printf("  %s", lrgc::apps::eval::calibrationReport(recall).c_str());
	RecordProperty("short_relations", std::to_string(rel.shortCount));
	RecordProperty("short_over_2deg_share", std::to_string(rel.shortOver2degShare()));
	RecordProperty("short_over_5deg", std::to_string(rel.shortOver5deg));
	RecordProperty("loop_recall", std::to_string(recall.recall()));
	RecordProperty("revisit_places", std::to_string(recall.places.size()));
	RecordProperty("false_closures", std::to_string(recall.falseClosures));
	RecordProperty("unmatched_scans", std::to_string(st.unmatchedScans));

	EXPECT_GT(recall.places.size(), 15U) << "the second lap must revisit the first";
	EXPECT_EQ(recall.falseClosures, 0U) << lrgc::apps::eval::recallReport(recall);
	// Issue 28's bars: < 1 % over 2 deg, recall >= 90 %. Main at 639db6f: 59 scans unmatched,
	// 31 / 589 over 2 deg (5.3 %), recall 12 / 21; porous anchors out of the free-space test:
	// 28 unmatched, 22 / 589 (3.7 %), 13 / 21. A failed plain match retried over the
	// odometry's heading error (CLocalRegistration::retriedMatch): 1 unmatched, 0 / 589,
	// 21 / 21 (doc/generalisation.md).
	EXPECT_LE(st.unmatchedScans, 5U);
	EXPECT_LT(rel.shortOver2degShare(), 0.01);
	EXPECT_GE(recall.recall(), 0.9);
}

/* The atrium (makeGlassAtriumWorld, 160 x 100 m, halls 12 m wide around a railed void, glass
 * returning 10 % of the beams), three laps of its halls' 392 m centre loop, as
 * `glass_stress world=atrium laps=3 seeds=2` (doc/generalisation.md). The east hall's
 * revisits are closed only by the end-of-run revisit sweep, and one old keyframe's scan there
 * is mostly isolated returns (the far walls 40-80 m away, one return a metre): matched against
 * that scan alone they fail. [RevisitLinker] region_retry matches them again against the old
 * map's region. Measured (session 65): recall 79 / 79 places, no false closure; with
 * region_retry off 70 / 79 (88.6 %, under issue 28's 90 %). */
TEST(GlassAtrium, revisitsOfFarWallsCloseAgainstTheOldMapsRegion)
{
	const uint32_t seed = 2;
	const CSyntheticWorld world = makeGlassAtriumWorld(seed, TGlassAtriumShape{});
	const double c = 10 + TGlassAtriumShape{}.hall / 2;  // the halls' centre lines
	const std::vector<Eigen::Vector2d> lap{
		{160 - c, c}, {160 - c, 100 - c}, {c, 100 - c}, {c, c}};
	std::vector<Eigen::Vector2d> wp{{30, c}};
	for (int i = 0; i < 3; ++i) wp.insert(wp.end(), lap.begin(), lap.end());
	wp.push_back(wp[0] + Eigen::Vector2d(28, 0));
	TOdometryNoise noise;
	noise.a1 *= 2, noise.a2 *= 2, noise.a3 *= 2, noise.a4 *= 2;
	TTrajectory tr = makeTrajectory(wp, 0.4, noise, 60 + seed, 0.6);
	scaleOdometry(tr, 1, 1);  // as glass_stress does (bias = scale = 1): the same odometry bits
	ASSERT_GT(minClearance(world, tr.truePoses), 0.5);
	CMetricMapBuilderLRGC builder;
	builder.setMinLoggingLevel(mrpt::system::LVL_ERROR);
	feedBuilder(builder, world, tr, longRangeSick(kPeriod, 80, 0.3, seed));

	const auto recall = truthLoopRecall(builder, tr.truePoses, kPeriod);
	std::printf(
		"[ glass atrium ] seed %u: loop recall %zu / %zu places, %zu false closures, "
		"%zu revisit links\n",
		seed, recall.closed, recall.places.size(), recall.falseClosures,
		builder.stats().revisitLinks);
	EXPECT_GE(recall.recall(), 0.9) << lrgc::apps::eval::recallReport(recall);
	EXPECT_EQ(recall.falseClosures, 0U) << lrgc::apps::eval::recallReport(recall);
}
