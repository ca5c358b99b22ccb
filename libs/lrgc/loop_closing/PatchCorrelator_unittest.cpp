/* CPatchCorrelator on synthetic segment worlds with known poses (PatchCorrelator_unittest.h):
 * branch and bound against the exhaustive search, stopped searches, patches with no
 * counterpart, repeated doors and featureless corridors, the k best peaks, the heading
 * window across +-pi, bad input. The search core's own tests are in
 * PatchCorrelator_search_unittest.cpp. */
#include <gtest/gtest.h>
#include <mrpt/math/wrap2pi.h>

#include <lrgc/loop_closing/PatchCorrelator.h>

#include "PatchCorrelator_unittest.h"

#include <algorithm>
#include <cmath>
#include <random>

using lrgc::CCorrelationGrid;
using lrgc::CPatchCorrelator;
using lrgc::CStopSource;
using lrgc::TCorrelationEffort;
using lrgc::TCorrelationResult;
using lrgc::TPatchCorrelatorParams;
using mrpt::math::TPose2D;
using Reason = lrgc::TCorrelationVerdict::Reason;
using namespace lrgc::test;

namespace
{
double angleDiff(double a, double b)
{
	return std::abs(mrpt::math::wrapToPi(a - b));
}

void expectSameResult(const TCorrelationResult& bnb, const TCorrelationResult& ex,
					  const TPatchCorrelatorParams& prm, int trial)
{
	EXPECT_EQ(bnb.patchInMap.x, ex.patchInMap.x) << "trial " << trial;
	EXPECT_EQ(bnb.patchInMap.y, ex.patchInMap.y) << "trial " << trial;
	EXPECT_EQ(bnb.patchInMap.phi, ex.patchInMap.phi) << "trial " << trial;
	EXPECT_EQ(bnb.score, ex.score) << "trial " << trial;
	EXPECT_TRUE(bnb.cov.isApprox(ex.cov)) << "trial " << trial;
	ASSERT_GE(ex.clusterPeaks.size(), 1u);
	// The exhaustive rival is exact. Branch and bound, whenever a rival could fail the
	// ambiguity filter, reports one that does (not necessarily the strongest): a pose outside
	// the cluster scoring at least S_best / min_ambiguity and at most the exact rival; inf
	// otherwise.
	const bool rivalMatters =
		ex.clusterPeaks.size() > 1 &&
		ex.clusterPeaks[1].score * prm.min_ambiguity >= ex.score * (1 - 1e-12);
	if (rivalMatters)
	{
		ASSERT_EQ(bnb.clusterPeaks.size(), 2u) << "trial " << trial;
		EXPECT_LE(bnb.clusterPeaks[1].score, ex.clusterPeaks[1].score) << "trial " << trial;
		EXPECT_GE(bnb.clusterPeaks[1].score * prm.min_ambiguity, ex.score * (1 - 1e-12))
			<< "trial " << trial;
		EXPECT_GE(bnb.ambiguity, ex.ambiguity) << "trial " << trial;
		EXPECT_LE(bnb.ambiguity, prm.min_ambiguity * (1 + 1e-12)) << "trial " << trial;
		const TPose2D r = bnb.clusterPeaks[1].patchInMap;
		EXPECT_TRUE(std::hypot(r.x - bnb.patchInMap.x, r.y - bnb.patchInMap.y) >
						prm.cluster_radius_m ||
					angleDiff(r.phi, bnb.patchInMap.phi) > prm.cluster_radius_phi)
			<< "trial " << trial << ": the rival lies outside the best cluster";
	}
	else
		EXPECT_TRUE(std::isinf(bnb.ambiguity)) << "trial " << trial;
	EXPECT_EQ(bnb.checkFilters(prm).rejection, ex.checkFilters(prm).rejection);
}
}  // namespace

TEST(PatchCorrelator, BranchAndBoundEqualsExhaustiveAndRecoversThePose)
{
	std::mt19937 rng(2024);
	std::uniform_real_distribution<double> u(-1, 1), inRoom(2.5, 9.5), ang(-M_PI, M_PI);
	int accepted = 0;
	for (int trial = 0; trial < 24; ++trial)
	{
		TPatchCorrelatorParams prm;
		prm.min_score = trial % 3 == 0 ? 0.0 : prm.min_score;  // also the unpruned search
		const CPatchCorrelator corr(prm);
		const World w = randomWorld(rng, 12, 10);
		const CCorrelationGrid map = corr.makeGrid(rasterise(w), 0.5);
		const TPose2D truth(inRoom(rng), inRoom(rng), ang(rng));
		const Points patch = makePatch(w, truth, 8, rng);
		const TPose2D center(truth.x + 0.3 * u(rng), truth.y + 0.3 * u(rng),
							 truth.phi + 0.05 * u(rng));
		const auto bnb = corr.correlate(map, patch, center, 0.5, 0.1);
		const auto ex = corr.correlateExhaustive(map, patch, center, 0.5, 0.1);
		ASSERT_EQ(bnb.has_value(), ex.has_value()) << "trial " << trial;
		ASSERT_TRUE(ex.has_value()) << "trial " << trial << ": the true pose is in the window";
		expectSameResult(*bnb, *ex, prm, trial);
		EXPECT_LT(bnb->posesScored, ex->posesScored) << "trial " << trial;
		// Within about one cell and one heading step of the truth.
		EXPECT_LE(std::abs(bnb->patchInMap.x - truth.x), 1.5 * prm.resolution_m) << trial;
		EXPECT_LE(std::abs(bnb->patchInMap.y - truth.y), 1.5 * prm.resolution_m) << trial;
		EXPECT_LE(angleDiff(bnb->patchInMap.phi, truth.phi), 1.5 * bnb->angularStep) << trial;
		accepted += bnb->passesFilters(TPatchCorrelatorParams{});
	}
	// A cluttered room seen by 8 scans is a distinctive match: nearly all pass the filters.
	EXPECT_GE(accepted, 22);
}

// Issue 30: a search stopped part-way finds nothing (its best so far is not the answer, and a
// rival not yet found is no evidence of no rival), in branch and bound and exhaustively.
TEST(PatchCorrelator, StoppedSearchFindsNothing)
{
	std::mt19937 rng(7);
	CPatchCorrelator corr;
	const World w = randomWorld(rng, 12, 10);
	const CCorrelationGrid map = corr.makeGrid(rasterise(w), 0.5);
	const TPose2D truth(6, 6, 0.3);
	const Points patch = makePatch(w, truth, 8, rng);
	ASSERT_TRUE(corr.correlate(map, patch, truth, 2.0, M_PI).has_value());
	const CStopSource source;
	corr.setStopToken(source.token());
	TCorrelationEffort effort;  // the stop comes after 4096 bound evaluations
	effort.onProgress = [&](const TCorrelationEffort& e)
	{
		if (e.posesScored >= 4096) source.requestStop();
	};
	EXPECT_FALSE(corr.correlate(map, patch, truth, 2.0, M_PI, &effort).has_value());
	EXPECT_TRUE(source.stopRequested());
	EXPECT_LT(effort.posesScored, 3 * 4096u);
	EXPECT_FALSE(corr.correlateExhaustive(map, patch, truth, 0.5, 0.1).has_value());
}

// patchCells() counts the cells a search scores (the loop closer weighs a grown patch by
// them before correlating it): points repeated, as a keyframe seeing only what the patch
// holds, add none.
TEST(PatchCorrelator, PatchCellsAreTheCellsASearchScores)
{
	std::mt19937 rng(11);
	CPatchCorrelator corr;
	const World w = randomWorld(rng, 12, 10);
	const CCorrelationGrid map = corr.makeGrid(rasterise(w), 0.5);
	const TPose2D truth(6, 6, 0.3);
	const Points patch = makePatch(w, truth, 8, rng);
	TCorrelationEffort effort;
	corr.correlate(map, patch, truth, 0.5, 0.1, &effort);
	EXPECT_EQ(corr.patchCells(patch), effort.patchCells);
	EXPECT_LT(corr.patchCells(patch), patch.size()) << "8 views of the same walls share cells";
	Points twice = patch;
	twice.insert(twice.end(), patch.begin(), patch.end());
	EXPECT_EQ(corr.patchCells(twice), corr.patchCells(patch));
	// Cells of 5 cm: x in [0, 0.05), [0.05, 0.1) and [-0.05, 0).
	EXPECT_EQ(corr.patchCells({{0.01, 0.01}, {0.04, 0.02}, {0.06, 0.01}, {-0.01, 0.01}}), 3u);
}

// A full-circle window has ~1000 headings here, so branch and bound bounds blocks of headings
// from their middle heading (correlation_search.cpp, headingBlockBound); the result must
// still be the exhaustive one, the rival included.
TEST(PatchCorrelator, BranchAndBoundInHeadingBlocksEqualsExhaustiveOverTheFullCircle)
{
	std::mt19937 rng(4242);
	std::uniform_real_distribution<double> u(-1, 1), inRoom(2.5, 9.5), ang(-M_PI, M_PI);
	for (int trial = 0; trial < 6; ++trial)
	{
		TPatchCorrelatorParams prm;
		prm.min_score = trial == 0 ? 0.0 : prm.min_score;
		const CPatchCorrelator corr(prm);
		const World w = randomWorld(rng, 12, 10);
		const CCorrelationGrid map = corr.makeGrid(rasterise(w), 0.5);
		const TPose2D truth(inRoom(rng), inRoom(rng), ang(rng));
		const Points patch = makePatch(w, truth, 8, rng);
		const TPose2D center(truth.x + 0.2 * u(rng), truth.y + 0.2 * u(rng), ang(rng));
		const auto bnb = corr.correlate(map, patch, center, 0.3, M_PI);
		const auto ex = corr.correlateExhaustive(map, patch, center, 0.3, M_PI);
		ASSERT_EQ(bnb.has_value(), ex.has_value()) << "trial " << trial;
		ASSERT_TRUE(ex.has_value()) << "trial " << trial;
		ASSERT_GT(2 * M_PI / bnb->angularStep, 256) << "heading blocks must be in use";
		expectSameResult(*bnb, *ex, prm, trial);
		EXPECT_LT(bnb->posesScored, ex->posesScored / 10) << "trial " << trial;
	}
}

TEST(PatchCorrelator, PatchWithoutCounterpartFailsTheFilters)
{
	std::mt19937 rng(77);
	std::uniform_real_distribution<double> inRoom(2.5, 6.5), ang(-M_PI, M_PI);
	const TPatchCorrelatorParams prm;
	const CPatchCorrelator corr(prm);
	int rejected = 0;
	const int trials = 10;
	for (int trial = 0; trial < trials; ++trial)
	{
		const World mapWorld = randomWorld(rng, 12, 10);
		const World otherWorld = randomWorld(rng, 9, 8);  // another room, other clutter
		const CCorrelationGrid map = corr.makeGrid(rasterise(mapWorld), 0.5);
		const TPose2D robot(inRoom(rng), inRoom(rng), ang(rng));
		const Points patch = makePatch(otherWorld, robot, 8, rng);
		const auto r = corr.correlate(map, patch, robot, 1.0, 0.2);
		rejected += !r || !r->passesFilters(prm);
		// The same search with no floor shows the best score really is low.
		TPatchCorrelatorParams noFloor = prm;
		noFloor.min_score = 0;
		const auto best = CPatchCorrelator(noFloor).correlate(map, patch, robot, 1.0, 0.2);
		ASSERT_TRUE(best.has_value());
		EXPECT_LT(best->score, 0.9) << "trial " << trial;
	}
	EXPECT_EQ(rejected, trials);
}

namespace
{
// Corridor along x (walls at y = +-1) from -20 to 20 m; with `period` > 0, a 0.9 m door
// every `period` metres in both walls, each with 0.4 m jambs.
World corridor(double period)
{
	World w;
	const double x0 = -20, x1 = 20, door = 0.9;
	for (const double y : {-1.0, 1.0})
	{
		if (period <= 0)
		{
			w.push_back({{x0, y}, {x1, y}});
			continue;
		}
		for (double x = x0; x < x1; x += period)
		{
			w.push_back({{x, y}, {x + period - door, y}});
			const double s = y > 0 ? 1 : -1;
			w.push_back({{x + period - door, y}, {x + period - door, y + 0.4 * s}});
			w.push_back({{x + period, y}, {x + period, y + 0.4 * s}});
		}
	}
	return w;
}
}  // namespace

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

namespace
{
// Doors every 3 m in a corridor (walls at y = +-1, as corridor()) from x = -20 to -5, a plain
// wall to x = -3, then a hall 5 m wide (walls at y = +-2.5) to x = 20: the doors' look-alikes
// end at x = -5.
World doorsThenHall()
{
	World w;
	const double door = 0.9, end = -3;
	for (const double y : {-1.0, 1.0})
	{
		const double s = y > 0 ? 1 : -1;
		double x = -20;
		for (; x + 3.0 <= end + 1e-9; x += 3.0)
		{
			w.push_back({{x, y}, {x + 3.0 - door, y}});
			w.push_back({{x + 3.0 - door, y}, {x + 3.0 - door, y + 0.4 * s}});
			w.push_back({{x + 3.0, y}, {x + 3.0, y + 0.4 * s}});
		}
		w.push_back({{x, y}, {end, y}});
		w.push_back({{end, y}, {end, 2.5 * s}});
		w.push_back({{end, 2.5 * s}, {20, 2.5 * s}});
	}
	return w;
}
}  // namespace

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

// The k best distinct poses (the far loop search's candidates): in the corridor of repeated
// doors, the truth, then each door 3 m away; peak 1 is correlate()'s best and peak 2 the
// exhaustive search's exact rival (the best pose outside peak 1's cluster).
TEST(PatchCorrelator, PeaksAreTheBestDistinctPosesBestFirst)
{
	std::mt19937 rng(5);
	const TPatchCorrelatorParams prm;
	const CPatchCorrelator corr(prm);
	const World w = corridor(3.0);
	const CCorrelationGrid map = corr.makeGrid(rasterise(w), 0.5);
	const TPose2D truth(0.4, 0.1, 0.02);
	const Points patch = makePatch(w, truth, 10, rng, 5.0);
	const auto peaks = corr.correlatePeaks(map, patch, truth, 3.5, 0.05, 5, 0.5);
	const auto best = corr.correlate(map, patch, truth, 3.5, 0.05);
	const auto ex = corr.correlateExhaustive(map, patch, truth, 3.5, 0.05);
	ASSERT_TRUE(best && ex);
	ASSERT_GE(peaks.size(), 3u);
	EXPECT_EQ(peaks[0].patchInMap.x, best->patchInMap.x);
	EXPECT_EQ(peaks[0].patchInMap.y, best->patchInMap.y);
	EXPECT_EQ(peaks[0].patchInMap.phi, best->patchInMap.phi);
	EXPECT_EQ(peaks[0].score, best->score);
	ASSERT_EQ(ex->clusterPeaks.size(), 2u);
	EXPECT_EQ(peaks[1].patchInMap.x, ex->clusterPeaks[1].patchInMap.x);
	EXPECT_EQ(peaks[1].patchInMap.y, ex->clusterPeaks[1].patchInMap.y);
	EXPECT_EQ(peaks[1].score, ex->clusterPeaks[1].score);
	std::vector<double> shifts;
	for (size_t n = 0; n < peaks.size(); ++n)
	{
		if (n > 0)
		{
			EXPECT_LE(peaks[n].score, peaks[n - 1].score);
		}
		EXPECT_GE(peaks[n].score, std::max(prm.min_score, 0.5 * peaks[0].score));
		for (size_t m = 0; m < n; ++m)
		{
			const TPose2D a = peaks[n].patchInMap, b = peaks[m].patchInMap;
			EXPECT_TRUE(std::hypot(a.x - b.x, a.y - b.y) > prm.cluster_radius_m ||
						angleDiff(a.phi, b.phi) > prm.cluster_radius_phi)
				<< "peaks " << m << " and " << n << " share a cluster";
		}
		shifts.push_back(peaks[n].patchInMap.x - truth.x);
	}
	std::sort(shifts.begin(), shifts.begin() + 3);
	EXPECT_NEAR(shifts[0], -3.0, 0.1) << "a door 3 m before";
	EXPECT_NEAR(shifts[1], 0.0, 1.5 * prm.resolution_m) << "the truth";
	EXPECT_NEAR(shifts[2], 3.0, 0.1) << "a door 3 m after";
	// A share of 1: only the poses as good as the best.
	const auto tied = static_cast<size_t>(std::count_if(
		peaks.begin(), peaks.end(), [&](const auto& p) { return p.score == peaks[0].score; }));
	EXPECT_EQ(corr.correlatePeaks(map, patch, truth, 3.5, 0.05, 5, 1.0).size(), tied);
}

// A ring of the window (TOriginRegion::beyondXY, the far search's rings): in the same corridor
// of doors 3 m apart, the peaks with the origin more than 1.5 m from the centre in x or y are
// the doors 3 m before and after, never the truth, and the first is the best of the whole
// window's peaks that lie in the ring.
TEST(PatchCorrelator, PeaksOfARingLieOutsideItsInnerSquare)
{
	std::mt19937 rng(5);
	const TPatchCorrelatorParams prm;
	const CPatchCorrelator corr(prm);
	const World w = corridor(3.0);
	const CCorrelationGrid map = corr.makeGrid(rasterise(w), 0.5);
	const TPose2D truth(0.4, 0.1, 0.02);
	const Points patch = makePatch(w, truth, 10, rng, 5.0);
	lrgc::TOriginRegion ring;
	ring.beyondXY = 1.5;
	const auto peaks = corr.correlatePeaks(map, patch, truth, 3.5, 0.05, 5, 0.5, 0, ring);
	ASSERT_GE(peaks.size(), 2u);
	const double inner = std::ceil(ring.beyondXY / prm.resolution_m - 1e-9) * prm.resolution_m;
	for (const auto& p : peaks)
		EXPECT_GT(
			std::max(std::abs(p.patchInMap.x - truth.x), std::abs(p.patchInMap.y - truth.y)),
			inner + 1e-9)
			<< "a peak inside the ring's inner square";
	std::vector<double> shifts{peaks[0].patchInMap.x - truth.x,
							   peaks[1].patchInMap.x - truth.x};
	std::sort(shifts.begin(), shifts.end());
	EXPECT_NEAR(shifts[0], -3.0, 0.1) << "a door 3 m before";
	EXPECT_NEAR(shifts[1], 3.0, 0.1) << "a door 3 m after";
	const auto all = corr.correlatePeaks(map, patch, truth, 3.5, 0.05, 5, 0.5);
	for (const auto& p : all)
		if (std::max(std::abs(p.patchInMap.x - truth.x), std::abs(p.patchInMap.y - truth.y)) >
			inner + 1e-9)
		{
			EXPECT_EQ(peaks[0].score, p.score) << "the ring's best is the window's best there";
			break;
		}
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

TEST(PatchCorrelator, HeadingWindowAcrossPlusMinusPiAndFullCircle)
{
	std::mt19937 rng(9);
	const TPatchCorrelatorParams prm;
	const CPatchCorrelator corr(prm);
	const World w = randomWorld(rng, 12, 10);
	const CCorrelationGrid map = corr.makeGrid(rasterise(w), 0.5);
	const TPose2D truth(6.1, 5.3, M_PI - 0.02);
	const Points patch = makePatch(w, truth, 8, rng);
	// Centre on the other side of the wrap: -pi + 0.03, i.e. 0.05 rad from the truth.
	const auto r = corr.correlate(map, patch, TPose2D(6.0, 5.4, -M_PI + 0.03), 0.5, 0.1);
	ASSERT_TRUE(r.has_value());
	EXPECT_LE(angleDiff(r->patchInMap.phi, truth.phi), 1.5 * r->angularStep);
	EXPECT_GT(r->patchInMap.phi, -M_PI);
	EXPECT_LE(r->patchInMap.phi, M_PI);
	EXPECT_TRUE(r->passesFilters(prm)) << r->checkFilters(prm).message();
	// Whole circle from a heading guess that is off by 2.3 rad; exhaustive agrees.
	const TPose2D far(6.1, 5.3, truth.phi + 2.3);
	const auto bnb = corr.correlate(map, patch, far, 0.1, M_PI);
	const auto ex = corr.correlateExhaustive(map, patch, far, 0.1, M_PI);
	ASSERT_TRUE(bnb.has_value() && ex.has_value());
	expectSameResult(*bnb, *ex, prm, -1);
	EXPECT_LE(angleDiff(bnb->patchInMap.phi, truth.phi), 1.5 * bnb->angularStep);
}

TEST(PatchCorrelator, EmptyPatchAndBadWindow)
{
	const CPatchCorrelator corr;
	const CCorrelationGrid map = corr.makeGrid({{0, 0}, {1, 1}}, 0.5);
	EXPECT_FALSE(corr.correlate(map, {}, TPose2D(0, 0, 0), 1, 0.1).has_value());
	const Points patch{{0.5, 0.5}};
	EXPECT_THROW(corr.correlate(map, patch, TPose2D(0, 0, 0), -1, 0.1), std::exception);
	EXPECT_THROW(corr.correlate(map, patch, TPose2D(0, std::nan(""), 0), 1, 0.1),
				 std::exception);
	EXPECT_THROW(corr.correlate(CCorrelationGrid{}, patch, TPose2D(0, 0, 0), 1, 0.1),
				 std::exception);
}
