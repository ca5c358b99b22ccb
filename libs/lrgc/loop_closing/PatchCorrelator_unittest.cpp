/* CPatchCorrelator on synthetic segment worlds with known poses (PatchCorrelator_unittest.h):
 * branch and bound against the exhaustive search, stopped searches, patches with no
 * counterpart, the k best peaks, the heading window across +-pi, bad input. Corridors and
 * straight ridges are in PatchCorrelator_corridor_unittest.cpp, the search core's own tests
 * in PatchCorrelator_search_unittest.cpp. */
#include <gtest/gtest.h>

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
