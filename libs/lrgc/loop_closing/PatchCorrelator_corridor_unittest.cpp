/* CPatchCorrelator in corridors (synthetic segment worlds of PatchCorrelator_unittest.h):
 * repeated doors as one straight ridge (the loop closer's near search, corridor_ridges) or
 * as rivals, a ridge that does not reach the gate's prediction, and a featureless corridor
 * rejected for its spread along the axis. */
#include <gtest/gtest.h>

#include <lrgc/loop_closing/PatchCorrelator.h>

#include "PatchCorrelator_unittest.h"

#include <cmath>
#include <random>

using lrgc::CCorrelationGrid;
using lrgc::CPatchCorrelator;
using lrgc::TPatchCorrelatorParams;
using mrpt::math::TPose2D;
using Reason = lrgc::TCorrelationVerdict::Reason;
using namespace lrgc::test;

// Doors every 3 m along a corridor: every copy of the patch lies on one straight ridge through
// the truth (the same heading, the same place across the corridor). Where the copies lie
// inside the window, the ridge is the best peak's own: the correlation fixes the pose across
// the corridor and the heading, and says how far along it the doubt reaches
// (TCorrelationResult::ridgeCovariance). Where a copy lies within a cluster radius of the
// window's border, the ridge may go on outside the window: it stays the rival, and filter 2
// rejects the patch as ambiguous.
TEST(PatchCorrelator, RepeatedDoorsAreOneRidgeInsideTheWindowAndAmbiguousAtItsBorder)
{
	std::mt19937 rng(5);
	const TPatchCorrelatorParams prm;
	CPatchCorrelator corr(prm);
	corr.setStraightRidges(true);  // the loop closer's near search
	const World w = corridor(3.0);
	const CCorrelationGrid map = corr.makeGrid(rasterise(w), 0.5);
	const TPose2D truth(0.4, 0.1, 0.02);
	const Points patch = makePatch(w, truth, 10, rng, 5.0);
	// A window of 3.2 m: the copies 3 m before and after lie at its border. The exact rival
	// (exhaustive search) is the next door, nearly as good as the truth.
	const auto ex = corr.correlateExhaustive(map, patch, truth, 3.2, 0.05);
	ASSERT_TRUE(ex.has_value());
	ASSERT_EQ(ex->clusterPeaks.size(), 2u);
	EXPECT_LT(ex->ambiguity, 1.05);
	const double shift = std::abs(ex->clusterPeaks[1].patchInMap.x - ex->patchInMap.x);
	EXPECT_NEAR(shift, 3.0, 0.1) << "the rival is the next door";
	// Branch and bound stops at the first rival that fails the filter: the same verdict.
	const auto r = corr.correlate(map, patch, truth, 3.2, 0.05);
	ASSERT_TRUE(r.has_value());
	ASSERT_EQ(r->clusterPeaks.size(), 2u);
	EXPECT_LT(r->ambiguity, prm.min_ambiguity);
	const auto v = r->checkFilters(prm);
	EXPECT_EQ(v.rejection, Reason::Ambiguous) << v.message();
	// A window of 4 m holds both copies: one ridge along the corridor (x), accepted; the
	// position across it (y) and the heading are the truth's, the doubt along it reaches both
	// doors (half-length >= 3 m, the far end at 2 sigma).
	const auto ridge = corr.correlate(map, patch, truth, 4.0, 0.05);
	ASSERT_TRUE(ridge.has_value());
	EXPECT_TRUE(ridge->passesFilters(prm)) << ridge->checkFilters(prm).message();
	EXPECT_NEAR(std::abs(ridge->ridgeAxis.x()), 1.0, 1e-3);
	EXPECT_GE(ridge->ridgeHalfLength, 3.0);
	const Eigen::Matrix3d C = ridge->ridgeCovariance();
	EXPECT_GE(std::sqrt(C(0, 0)), 1.5) << "along the corridor";
	EXPECT_LT(std::sqrt(C(1, 1)), 1e-6) << "across the corridor";
	EXPECT_NEAR(ridge->patchInMap.y, truth.y, 1.5 * prm.resolution_m);
	EXPECT_LE(std::abs(angleDiff(ridge->patchInMap.phi, truth.phi)), prm.max_std_phi);
	// With a window too small to hold a copy, the same patch is unambiguous and accepted, and
	// no ridge reaches past a cluster radius of the window's border.
	const auto local = corr.correlate(map, patch, truth, 1.0, 0.05);
	ASSERT_TRUE(local.has_value());
	EXPECT_TRUE(local->passesFilters(prm)) << local->checkFilters(prm).message();
	EXPECT_TRUE(local->ridgeAxis.isZero());
	EXPECT_LE(std::abs(local->patchInMap.x - truth.x), 1.5 * prm.resolution_m);
	// Without straight ridges (the far search's correlators) the doors are rivals.
	const auto paper = CPatchCorrelator(prm).correlate(map, patch, truth, 4.0, 0.05);
	ASSERT_TRUE(paper.has_value());
	EXPECT_EQ(paper->checkFilters(prm).rejection, Reason::Ambiguous);
	EXPECT_TRUE(paper->ridgeAxis.isZero());
}

// A straight ridge is the robot's corridor slide only where its first step reaches the
// window's centre (the gate's prediction) within a cluster radius: the first 300 scans of
// SparseScans.TurnsOfEightyDegrees had a ridge of +-3.7 m 8.9 m from the prediction, and its
// link, seeded at the ridge's end, landed 5.6 m along the corridor from the truth. Here the
// doors' look-alikes lie 3 m apart west of x = -5; a window centred 8.5 m east of the truth
// holds the truth and its look-alikes 3 m east and west; the prediction lies 5.5 m or more
// from the best pose (a look-alike or the truth), beyond the first step's reach (3.5 m and a
// cluster radius): the look-alike is the rival (ambiguous). Centred 0.5 m from the truth, the
// same look-alikes are the ridge of the robot's corridor, accepted. One heading (the window
// +-0.005 rad, less than a step): the rule's premise, look-alikes at the best's heading, holds
// by construction.
TEST(PatchCorrelator, AStraightRidgeThatDoesNotReachThePredictionIsAmbiguous)
{
	std::mt19937 rng(7);
	const TPatchCorrelatorParams prm;
	CPatchCorrelator corr(prm);
	corr.setStraightRidges(true);
	const World w = doorsThenHall();
	const CCorrelationGrid map = corr.makeGrid(rasterise(w), 0.5);
	const TPose2D truth(-10.6, 0.1, 0.02);
	const Points patch = makePatch(w, truth, 10, rng, 4.0);
	const TPose2D far(truth.x + 8.5, truth.y, truth.phi);
	const auto away = corr.correlate(map, patch, far, 10.0, 0.005);
	ASSERT_TRUE(away.has_value());
	EXPECT_LT(std::abs(std::remainder(away->patchInMap.x - truth.x, 3.0)), 0.1)
		<< "the best pose is the truth or a door's look-alike";
	const auto v = away->checkFilters(prm);
	EXPECT_EQ(v.rejection, Reason::Ambiguous) << v.message();
	EXPECT_TRUE(away->ridgeAxis.isZero());
	ASSERT_EQ(away->clusterPeaks.size(), 2u);
	const TPose2D rival = away->clusterPeaks[1].patchInMap;
	EXPECT_NEAR(std::abs(rival.x - away->patchInMap.x), 3.0, 0.2) << "the look-alike";
	EXPECT_NEAR(rival.y, away->patchInMap.y, 1.5 * prm.resolution_m);

	const TPose2D near(truth.x + 0.5, truth.y, truth.phi);
	const auto ridge = corr.correlate(map, patch, near, 4.0, 0.005);
	ASSERT_TRUE(ridge.has_value());
	EXPECT_TRUE(ridge->passesFilters(prm)) << ridge->checkFilters(prm).message();
	EXPECT_NEAR(std::abs(ridge->ridgeAxis.x()), 1.0, 1e-3);
	EXPECT_GE(ridge->ridgeHalfLength, 3.0);
}

TEST(PatchCorrelator, FeaturelessCorridorIsRejectedForItsSpreadAlongTheAxis)
{
	std::mt19937 rng(6);
	TPatchCorrelatorParams prm;
	prm.cluster_radius_m = 10;  // one cluster over the whole window: the variance decides
	const CPatchCorrelator corr(prm);
	const World w = corridor(0);
	const CCorrelationGrid map = corr.makeGrid(rasterise(w), 0.5);
	const TPose2D truth(0.4, 0.1, 0.0);
	const Points patch = makePatch(w, truth, 10, rng, 5.0);
	const auto r = corr.correlate(map, patch, truth, 1.0, 0.05);
	ASSERT_TRUE(r.has_value());
	EXPECT_GT(std::sqrt(r->cov(0, 0)), prm.max_std_xy_m) << "along the corridor";
	EXPECT_LT(std::sqrt(r->cov(1, 1)), 0.05) << "across the corridor";
	EXPECT_NEAR(r->patchInMap.y, truth.y, 1.5 * prm.resolution_m);
	EXPECT_EQ(r->checkFilters(prm).rejection, Reason::SpreadXY);
	// With the default cluster radius, poses further along score as well: ambiguous.
	const auto d = CPatchCorrelator().correlate(map, patch, truth, 1.0, 0.05);
	ASSERT_TRUE(d.has_value());
	EXPECT_FALSE(d->passesFilters(TPatchCorrelatorParams{}));
}
