/* CLoopCloser's patch: keyframesWithinTravel, the path-length cap ([LoopCloser]
 * patch_max_travel_m: keyframes 1 m apart (sparse scans) and 0.35 m apart (dense logs), and
 * turns on the spot, which add keyframes but no path); its growth for ambiguity, tried after an
 * ambiguous sigma patch, and only when it adds cells; the far check's reference (visitAround);
 * the loop link's references in the order tried; the patch's points (patchPoints). */
#include <gtest/gtest.h>
#include <lrgc/loop_closing/LoopCloser.h>
#include <lrgc/loop_closing/LoopCloserParams.h>

using namespace lrgc;
using mrpt::math::TPose2D;

namespace
{
CPoseGraph straightLine(size_t nodes, double step)
{
	CPoseGraph g;
	for (size_t i = 0; i < nodes; ++i) g.addNode(TPose2D(double(i) * step, 0, 0));
	return g;
}
}  // namespace

TEST(LoopCloserPatch, sparseKeyframesAreCappedByThePathTheyCover)
{
	// 60 keyframes 1 m apart: the newest and the 24 before it lie within 24 m of path.
	EXPECT_EQ(CLoopCloser::keyframesWithinTravel(straightLine(60, 1.0), 24.0), 25u);
	// Fewer keyframes than the cap covers: all of them.
	EXPECT_EQ(CLoopCloser::keyframesWithinTravel(straightLine(10, 1.0), 24.0), 10u);
	EXPECT_EQ(CLoopCloser::keyframesWithinTravel(straightLine(1, 1.0), 24.0), 1u);
}

TEST(LoopCloserPatch, denseKeyframesUnderTheDefaultCapKeepTheirFortyKeyframePatch)
{
	// 0.35 m apart (the benchmark logs' median spacing): 40 keyframes span 13.65 m.
	const TLoopCloserParams p;
	EXPECT_GE(CLoopCloser::keyframesWithinTravel(straightLine(200, 0.35), p.patch_max_travel_m),
			  p.old_map_exclusion_keyframes);
}

TEST(LoopCloserPatch, turningOnTheSpotAddsNoPath)
{
	CPoseGraph g = straightLine(30, 1.0);
	for (int i = 1; i <= 5; ++i) g.addNode(TPose2D(29, 0, 0.5 * i));
	// 5 turned keyframes at the same place, then 25 within 24 m along the line.
	EXPECT_EQ(CLoopCloser::keyframesWithinTravel(g, 24.0), 30u);
}

// [LoopCloser] patch_keyframes_per_ambiguity: a near correlation rejected as ambiguous grows
// the next patch by 10 keyframes, up to old_map_exclusion_keyframes; other rejections and the
// far search's correlations leave it as it was.
TEST(LoopCloserPatch, anAmbiguousNearCorrelationGrowsThePatch)
{
	TLoopCloserParams p;
	p.patch_keyframes_per_ambiguity = 10;  // the default
	TCorrelationVerdict ambiguous;
	ambiguous.rejection = TCorrelationVerdict::Reason::Ambiguous;
	TCorrelationVerdict lowScore;
	lowScore.rejection = TCorrelationVerdict::Reason::LowScore;
	size_t growth = CLoopCloser::grownAfter(p, 0, ambiguous, true);
	EXPECT_EQ(growth, p.patch_keyframes_per_ambiguity);
	EXPECT_EQ(CLoopCloser::grownAfter(p, growth, lowScore, true), growth);
	EXPECT_EQ(CLoopCloser::grownAfter(p, growth, ambiguous, false), growth) << "far search";
	for (int i = 0; i < 10; ++i) growth = CLoopCloser::grownAfter(p, growth, ambiguous, true);
	EXPECT_EQ(growth, p.old_map_exclusion_keyframes);
	// The calibrated gate's 0.5 m std asks for 10 + 8 * 0.5 = 14 keyframes; two ambiguous
	// rejections make it 34, the cap 40.
	EXPECT_EQ(CLoopCloser::patchKeyframes(p, 0.5, 0), 14u);
	EXPECT_EQ(CLoopCloser::patchKeyframes(p, 0.5, 2 * p.patch_keyframes_per_ambiguity), 34u);
	EXPECT_EQ(CLoopCloser::patchKeyframes(p, 0.5, growth), p.old_map_exclusion_keyframes);
}

// The grown patch is a second try in the same check, never the first: it is correlated only
// after the sigma's patch of a near search was rejected as ambiguous, and only when it is
// larger (the caps may leave it the same size).
TEST(LoopCloserPatch, theGrownPatchIsTriedOnlyAfterAnAmbiguousSigmaPatch)
{
	TLoopCloserParams p;
	ASSERT_GT(p.patch_keyframes_per_ambiguity, 0u) << "on by default";
	TCorrelationVerdict ambiguous, lowScore, spread, accepted;
	ambiguous.rejection = TCorrelationVerdict::Reason::Ambiguous;
	lowScore.rejection = TCorrelationVerdict::Reason::LowScore;
	spread.rejection = TCorrelationVerdict::Reason::SpreadXY;
	EXPECT_TRUE(CLoopCloser::retriesGrown(p, ambiguous, true, 14, 24));
	EXPECT_FALSE(CLoopCloser::retriesGrown(p, accepted, true, 14, 24)) << "accepted";
	EXPECT_FALSE(CLoopCloser::retriesGrown(p, lowScore, true, 14, 24)) << "low score";
	EXPECT_FALSE(CLoopCloser::retriesGrown(p, spread, true, 14, 24)) << "spread";
	EXPECT_FALSE(CLoopCloser::retriesGrown(p, ambiguous, false, 14, 24)) << "far search";
	EXPECT_FALSE(CLoopCloser::retriesGrown(p, ambiguous, true, 40, 40)) << "at the cap";
	p.patch_keyframes_per_ambiguity = 0;
	EXPECT_FALSE(CLoopCloser::retriesGrown(p, ambiguous, true, 14, 24)) << "off";
}

// The grown patch is correlated only when it adds cells to the sigma's: on MIT Killian's b80
// variant (keyframes 1.5 m apart) the keyframes it adds lie beyond patch_max_range_m and its
// cells were the sigma's (1088 -> 1088) or 2 % more (1044 -> 1067), rejected as ambiguous
// again at the same cost; the grown patches that passed the filters added 39 % (sparse ACES,
// 1235 -> 1720) and more.
TEST(LoopCloserPatch, aGrownPatchIsCorrelatedOnlyWhenItAddsCells)
{
	TLoopCloserParams p;
	EXPECT_FALSE(CLoopCloser::grownAddsCells(p, 1088, 1088));
	EXPECT_FALSE(CLoopCloser::grownAddsCells(p, 1044, 1067));
	EXPECT_TRUE(CLoopCloser::grownAddsCells(p, 1235, 1720));
	EXPECT_TRUE(CLoopCloser::grownAddsCells(p, 1000, 1200)) << "the share itself";
	p.patch_grown_min_new_cells = 0;
	EXPECT_TRUE(CLoopCloser::grownAddsCells(p, 1088, 1088)) << "0: always";
}

// The far check's loop-link reference is the pass through the matched old keyframe: keyframes
// 106-135 (the first corridor) and 918-954 (another side of the loop, which the drift laid on
// it in the map) are both near the place; only the first pass is the place's.
TEST(LoopCloserFarCheck, theReferenceIsThePassThroughTheMatchedKeyframe)
{
	std::vector<size_t> near;
	for (size_t j = 954; j >= 918; --j) near.push_back(j);
	for (size_t j = 135; j >= 106; --j) near.push_back(j);
	near.push_back(110);  // a duplicate is harmless
	const auto visit = CLoopCloser::visitAround(near, 120, 3);
	ASSERT_FALSE(visit.empty());
	EXPECT_EQ(visit.front(), 106u);
	EXPECT_EQ(visit.back(), 135u);
	// A gap of up to 3 indices (keyframes turned away) stays one pass; 4 splits it.
	EXPECT_EQ(CLoopCloser::visitAround({10, 13, 16, 20}, 13, 3),
			  (std::vector<size_t>{10, 13, 16}));
	EXPECT_TRUE(CLoopCloser::visitAround({10, 13}, 12, 3).empty()) << "not a candidate";
}

// Step 3's loop-link match is refused against both passes through a place (keyframes 0-8 and
// 44-46 on sparse MIT-CSAIL, laid down a metre apart before the loop closed): it is tried again
// against the pass holding the matched old keyframe alone. One pass near the place, or the far
// check (only the matched pass), leaves one reference.
TEST(LoopCloserMatch, aMatchRefusedAgainstTwoPassesIsTriedOnThePassOfTheMatchedKeyframe)
{
	const std::vector<size_t> twoPasses = {0, 1, 2, 3, 5, 6, 7, 8, 44, 45, 46};
	const auto refs = CLoopCloser::loopMatchReferences(twoPasses, 45, false, 3);
	ASSERT_EQ(refs.size(), 2u);
	EXPECT_EQ(refs.front(), twoPasses) << "every pass first";
	EXPECT_EQ(refs.back(), (std::vector<size_t>{44, 45, 46}));
	EXPECT_EQ(CLoopCloser::loopMatchReferences(twoPasses, 2, false, 3).back(),
			  (std::vector<size_t>{0, 1, 2, 3, 5, 6, 7, 8}));

	const std::vector<size_t> onePass = {44, 45, 46};
	EXPECT_EQ(CLoopCloser::loopMatchReferences(onePass, 45, false, 3),
			  (std::vector<std::vector<size_t>>{onePass}));
	EXPECT_EQ(CLoopCloser::loopMatchReferences(twoPasses, 45, true, 3),
			  (std::vector<std::vector<size_t>>{{44, 45, 46}}))
		<< "far check";
	EXPECT_EQ(CLoopCloser::loopMatchReferences(twoPasses, 20, false, 3),
			  (std::vector<std::vector<size_t>>{twoPasses}))
		<< "matched keyframe not among them";
}

// The patch keeps the points within patch_max_range_m of the newest keyframe; of an older
// keyframe's, those it saw beyond that range through a gap (a beam within two returned more
// than patch_far_gap_m nearer: between a railing's posts) are left out, a far wall seen along
// itself is kept.
TEST(LoopCloserPatch, anOlderKeyframesFarPointSeenThroughAGapIsLeftOut)
{
	const CPoseGraph g = straightLine(2, 10.0);  // keyframes at x = 0 and 10 m
	TScan2D old, newest;
	// Beam order, in the old keyframe's frame: a point 21 m off between posts at 6 m; two
	// returns 25 m off (20.6 m from the newest: out of range); a far wall seen along itself,
	// 20.5-20.8 m off (10.5-10.8 m from the newest), its neighbours as far.
	old.points = {{6, 1.75}, {21, 2},     {6, 2.25},   {15, 20},
				  {15, 20},  {20.5, 0.5}, {20.625, 1}, {20.75, 1.5}};
	newest.points = {{3, 0}, {-13, 0}};  // x 13; x -3 (13 m from it)
	const TScanRefs scans{&old, &newest};
	double radius = 0;
	const auto patch = CLoopCloser::patchPoints(g, scans, 0, 12.0, 0.5, radius);
	const std::vector<Eigen::Vector2d> expected{{-4, 1.75},  {-4, 2.25},   {10.5, 0.5},
												{10.625, 1}, {10.75, 1.5}, {3, 0}};
	EXPECT_EQ(patch, expected);  // the newest's frame; (21, 2) seen between the posts
	EXPECT_NEAR(radius, std::hypot(10.75, 1.5), 1e-12);
	EXPECT_EQ(CLoopCloser::patchPoints(g, scans, 0, 12.0, 0.0, radius).size(), 7u) << "0: kept";
	EXPECT_EQ(CLoopCloser::patchPoints(g, scans, 1, 12.0, 0.5, radius).size(), 1u);
}

// A re-match after a closure is checked against the solve in both axes
// (CLoopCloser::rematchDisagreementChi2). Two keyframes facing opposite ways (z turned by 180
// deg), matched loosely with slide and turn coupled (sd 1 m along x, 9.2 deg, correlation
// 0.95: dense Killian's 1608 -> 3693): a disagreement against the coupling reads as one along
// it in z's axes (chi2 2.6, kept on main) and is refused in i's axes. A link that does not
// turn reads alike both ways; the solve's own error lets a closer match 0.15 m from it pass.
TEST(LoopCloserRematch, aLooseMatchOfOppositePassesIsReadInItsOwnAxes)
{
	const double sx = 1.0, sphi = 0.16, rho = 0.95;
	Eigen::Matrix3d cov;
	cov << sx * sx, 0, rho * sx * sphi, 0, 0.01, 0, rho * sx * sphi, 0, sphi * sphi;
	const Eigen::Matrix3d info = cov.inverse();
	const Eigen::Matrix3d noSolveError = Eigen::Matrix3d::Zero();
	const TPose2D xi(0, 0, 0), z(0, 0, M_PI);
	const TPose2D againstCoupling(1.3, 0, M_PI - 0.15);  // x +1.3 m with heading -0.15 rad
	const Eigen::Vector3d eZ = linkResidual(xi, againstCoupling, z);
	EXPECT_LT(eZ.dot(info * eZ), 5.0) << "the back end's reading alone keeps it";
	EXPECT_GT(CLoopCloser::rematchDisagreementChi2(xi, againstCoupling, z, info, noSolveError),
			  15.0);

	const TPose2D straight(0, 0, 0), ahead(1.3, 0, 0.15);
	const Eigen::Vector3d eS = linkResidual(xi, ahead, straight);
	EXPECT_NEAR(CLoopCloser::rematchDisagreementChi2(xi, ahead, straight, info, noSolveError),
				eS.dot(info * eS), 1e-9);

	// A closer match (sd 0.1 m, 1 deg, x and heading correlated 0.9) 0.15 m / 0.46 deg from the
	// solve against its coupling: chi2 6.4 in z's axes, 19.5 in i's; the solve's own error
	// (0.15 m, 1 deg) brings the latter to 1.1.
	const double d1 = mrpt::DEG2RAD(1.0);
	Eigen::Matrix3d closeCov;
	closeCov << 0.01, 0, 0.9 * 0.1 * d1, 0, 0.01, 0, 0.9 * 0.1 * d1, 0, d1 * d1;
	const Eigen::Matrix3d closeInfo = closeCov.inverse();
	const TPose2D off(0.15, 0, M_PI - 0.008);
	const Eigen::Matrix3d solveError = Eigen::Vector3d(0.0225, 0.0225, d1 * d1).asDiagonal();
	EXPECT_GT(CLoopCloser::rematchDisagreementChi2(xi, off, z, closeInfo, noSolveError), 15.0);
	EXPECT_NEAR(CLoopCloser::rematchDisagreementChi2(xi, off, z, closeInfo, solveError), 6.44,
				0.05);
}
