/* CPatchCorrelator on synthetic segment worlds with known poses.
 *
 * A small generator lives here (a shared synthetic world is being written separately): a
 * world is a set of wall segments; the old map is the walls sampled every 2 cm; a patch is
 * the ray-cast scans (180 beams, 1 cm noise) of a short robot path, expressed in the frame
 * of the path's last pose, which is therefore the true patchInMap.
 */
#include <gtest/gtest.h>
#include <mrpt/math/wrap2pi.h>

#include <lrgc/loop_closing/PatchCorrelator.h>
#include <lrgc/common/se2.h>

#include "correlation_search.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

using lrgc::CCorrelationGrid;
using lrgc::CPatchCorrelator;
using lrgc::CStopSource;
using lrgc::TCorrelationEffort;
using lrgc::TCorrelationResult;
using lrgc::TPatchCorrelatorParams;
using mrpt::math::TPose2D;
using Reason = lrgc::TCorrelationVerdict::Reason;
using Points = std::vector<Eigen::Vector2d>;

namespace
{
struct Segment
{
	Eigen::Vector2d a, b;
};
using World = std::vector<Segment>;

// A square room of side `size` with `n` random interior walls (0.5 to 3 m).
World randomWorld(std::mt19937& rng, double size, int n)
{
	World w{{{0, 0}, {size, 0}},
			{{size, 0}, {size, size}},
			{{size, size}, {0, size}},
			{{0, size}, {0, 0}}};
	std::uniform_real_distribution<double> pos(0.5, size - 0.5), len(0.5, 3.0),
		ang(-M_PI, M_PI);
	for (int k = 0; k < n; ++k)
	{
		const Eigen::Vector2d a(pos(rng), pos(rng));
		const double t = ang(rng), l = len(rng);
		w.push_back({a, a + l * Eigen::Vector2d(std::cos(t), std::sin(t))});
	}
	return w;
}

Points rasterise(const World& w, double spacing = 0.02)
{
	Points pts;
	for (const auto& s : w)
	{
		const int n = std::max(1, int(std::ceil((s.b - s.a).norm() / spacing)));
		for (int k = 0; k <= n; ++k) pts.push_back(s.a + (s.b - s.a) * (double(k) / n));
	}
	return pts;
}

// Scan from `robot`: nearest hit of each beam (-90..+90 deg) in the robot frame.
Points raycast(const World& w, const TPose2D& robot, std::mt19937& rng, double maxRange)
{
	std::normal_distribution<double> noise(0, 0.01);
	Points pts;
	const Eigen::Vector2d o(robot.x, robot.y);
	for (int k = 0; k < 180; ++k)
	{
		const double beam = -M_PI / 2 + M_PI * k / 179.0;
		const Eigen::Vector2d d(std::cos(robot.phi + beam), std::sin(robot.phi + beam));
		double best = maxRange;
		for (const auto& s : w)
		{
			const Eigen::Vector2d e = s.b - s.a, r = s.a - o;
			const double den = d.x() * e.y() - d.y() * e.x();
			if (std::abs(den) < 1e-12) continue;
			const double t = (r.x() * e.y() - r.y() * e.x()) / den;
			const double u = (r.x() * d.y() - r.y() * d.x()) / den;
			if (t > 0.05 && u >= 0 && u <= 1) best = std::min(best, t);
		}
		if (best >= maxRange) continue;
		const double r = best + noise(rng);
		pts.emplace_back(r * std::cos(beam), r * std::sin(beam));
	}
	return pts;
}

// Patch of `n` scans along a path ending at `last` (straight, 0.15 m per scan), in the
// frame of `last`.
Points makePatch(const World& w, const TPose2D& last, int n, std::mt19937& rng,
				 double maxRange = 8.0)
{
	Points patch;
	for (int k = n - 1; k >= 0; --k)
	{
		const TPose2D robot = lrgc::compose(last, TPose2D(-0.15 * k, 0, 0.01 * k));
		const TPose2D robotInPatch = lrgc::between(last, robot);
		for (const auto& p : raycast(w, robot, rng, maxRange))
			patch.push_back(lrgc::transformPoint(robotInPatch, p));
	}
	return patch;
}

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
/** A pose-grid problem's base cells (map cells, per heading then per point): heading a
 * (0 .. numAngles - 1) turns the patch to robot.phi + (a + a0) dtheta [rad], placed at robot.
 */
void appendBaseCells(lrgc::detail::TPoseGridProblem& pb, const CCorrelationGrid& map,
					 const TPose2D& robot, const Points& patch, int a0, double dtheta)
{
	for (int a = 0; a < pb.numAngles; ++a)
	{
		const double th = robot.phi + (a + a0) * dtheta, c = std::cos(th), sn = std::sin(th);
		for (const auto& p : patch)
		{
			const Eigen::Vector2i cell = map.cellOf(
				{robot.x + c * p.x() - sn * p.y(), robot.y + sn * p.x() + c * p.y()});
			pb.baseCells.push_back(cell.x());
			pb.baseCells.push_back(cell.y());
		}
	}
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

// The bound of a node spanning several headings (branch and bound over the full circle) is at
// least every exact score of its headings and translations: random blocks of a real problem
// (a room seen by 8 scans, 0.05 m cells, the correlator's own heading step).
TEST(PatchCorrelator, HeadingBlockBoundIsAtLeastEveryScoreOfItsBlock)
{
	std::mt19937 rng(99);
	std::uniform_real_distribution<double> inRoom(2.5, 9.5), ang(-M_PI, M_PI);
	const CPatchCorrelator corr;
	const World w = randomWorld(rng, 12, 10);
	const CCorrelationGrid map = corr.makeGrid(rasterise(w), 0.5);
	const TPose2D robot(inRoom(rng), inRoom(rng), ang(rng));
	const Points patch = makePatch(w, robot, 8, rng);
	double maxR = 0;
	for (const auto& p : patch) maxR = std::max(maxR, p.norm());
	const double res = map.resolution(), dtheta = res / maxR;
	lrgc::detail::TPoseGridProblem pb;
	pb.grid = &map;
	pb.numPoints = int(patch.size());
	pb.halfCells = 40;
	pb.numAngles = 200;
	pb.cellsPerAngleStep = maxR * dtheta / res;
	appendBaseCells(pb, map, robot, patch, -100, dtheta);
	pb.prepare();
	std::uniform_int_distribution<int> level(0, 4), angle(0, pb.numAngles - 1), cell(-40, 30);
	int tightBlocks = 0;
	for (int trial = 0; trial < 300; ++trial)
	{
		const int h = level(rng);
		const int a0 = angle(rng), a1 = std::min(pb.numAngles - 1, a0 + (1 << level(rng)));
		const int i0 = cell(rng), j0 = cell(rng);
		int64_t best = 0;
		for (int a = a0; a <= a1; ++a)
			for (int i = i0; i < i0 + (1 << h); ++i)
				for (int j = j0; j < j0 + (1 << h); ++j)
					best = std::max(best, lrgc::detail::scoreAt(pb, 0, a, i, j));
		const int64_t bound = lrgc::detail::blockBound(pb, a0, a1, h, i0, j0,
													   std::numeric_limits<int64_t>::min());
		ASSERT_GE(bound, best) << "headings " << a0 << ".." << a1 << ", level " << h
							   << ", cells (" << i0 << ", " << j0 << ")";
		tightBlocks += bound < int64_t(255) * pb.numPoints;
	}
	EXPECT_GT(tightBlocks, 250) << "the bound must prune, not just be 255 N";
}

// The far search's peaks in one best-first pass (detail::searchPeaks) are exactly those of
// the exhaustive search run again and again, each time with the clusters of the peaks before
// excluded and, after the first, the floor at 0.6 of its score: with and without a region the
// translations are restricted to (setAllowed), with one heading per node (60 headings) and
// with blocks of headings (300).
TEST(PatchCorrelator, PeaksInOnePassEqualRepeatedExhaustiveSearches)
{
	std::mt19937 rng(777);
	std::uniform_real_distribution<double> inRoom(2.5, 9.5), ang(-M_PI, M_PI);
	TPatchCorrelatorParams prm;
	prm.resolution_m = 0.2, prm.blur_sigma_m = 0.2;
	const CPatchCorrelator corr(prm);
	for (int trial = 0; trial < 4; ++trial)
	{
		const World w = randomWorld(rng, 12, 10);
		const CCorrelationGrid map = corr.makeGrid(rasterise(w), 0.6);
		const TPose2D robot(inRoom(rng), inRoom(rng), ang(rng));
		const Points patch = makePatch(w, robot, 6, rng);
		lrgc::detail::TPoseGridProblem pb;
		pb.grid = &map;
		pb.numPoints = int(patch.size());
		pb.halfCells = trial < 2 ? 20 : 8;
		pb.numAngles = trial < 2 ? 60 : 300;
		double maxR = 0;
		for (const auto& p : patch) maxR = std::max(maxR, p.norm());
		const double dtheta = 2 * M_PI / pb.numAngles;
		pb.cellsPerAngleStep = maxR * dtheta / map.resolution();
		appendBaseCells(pb, map, robot, patch, 0, dtheta);
		pb.prepare();
		if (trial % 2 == 1)
		{  // translations allowed only in two discs of 5 cells
			std::vector<uint8_t> level0(size_t(pb.side()) * size_t(pb.side()), 0);
			for (int i = -pb.halfCells; i <= pb.halfCells; ++i)
				for (int j = -pb.halfCells; j <= pb.halfCells; ++j)
					if (std::hypot(i - 3, j + 2) <= 5 || std::hypot(i + 6, j - 5) <= 5)
						level0[size_t(i + pb.halfCells) * size_t(pb.side()) +
							   size_t(j + pb.halfCells)] = 1;
			pb.setAllowed(level0, map.numLevels());
		}
		const auto clusterOf = [&](const lrgc::detail::TSearchHit& hit)
		{
			lrgc::detail::TExclusionDisc d;
			d.inAngle.resize(size_t(pb.numAngles));
			for (int a = 0; a < pb.numAngles; ++a)
				d.inAngle[size_t(a)] = std::abs(a - hit.a) <= 3;
			d.ci = hit.i, d.cj = hit.j, d.r2 = 9;
			return d;
		};
		const int64_t floor = int64_t(0.2 * 255 * pb.numPoints);
		lrgc::detail::TExclusionZone zone;
		const auto found = lrgc::detail::searchPeaks(pb, floor, 0.6, 6, zone,
													 [&](const lrgc::detail::TSearchHit& hit)
													 { zone.discs.push_back(clusterOf(hit)); });
		const auto& peaks = found.peaks;
		EXPECT_GE(found.evaluations, peaks.size());
		lrgc::detail::TExclusionZone refZone;
		int64_t refFloor = floor;
		std::vector<lrgc::detail::TSearchHit> ref;
		while (ref.size() < 6)
		{
			const auto hit = lrgc::detail::searchExhaustive(pb, refFloor, refZone);
			if (!hit.found) break;
			ref.push_back(hit);
			if (ref.size() == 1)
				refFloor =
					std::max(refFloor, int64_t(std::ceil(0.6 * double(hit.score) - 1e-9)));
			refZone.discs.push_back(clusterOf(hit));
		}
		ASSERT_GE(ref.size(), 2u) << "trial " << trial << ": the test needs several peaks";
		ASSERT_EQ(peaks.size(), ref.size()) << "trial " << trial;
		for (size_t n = 0; n < ref.size(); ++n)
		{
			EXPECT_EQ(peaks[n].score, ref[n].score) << "trial " << trial << ", peak " << n;
			EXPECT_EQ(peaks[n].a, ref[n].a) << "trial " << trial << ", peak " << n;
			EXPECT_EQ(peaks[n].i, ref[n].i) << "trial " << trial << ", peak " << n;
			EXPECT_EQ(peaks[n].j, ref[n].j) << "trial " << trial << ", peak " << n;
			if (trial % 2 == 1)
			{
				EXPECT_TRUE(pb.blockAllowed(0, peaks[n].i, peaks[n].j));
			}
		}
	}
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

TEST(PatchCorrelator, RepeatedDoorsAreRejectedAsAmbiguous)
{
	std::mt19937 rng(5);
	const TPatchCorrelatorParams prm;
	const CPatchCorrelator corr(prm);
	const World w = corridor(3.0);
	const CCorrelationGrid map = corr.makeGrid(rasterise(w), 0.5);
	const TPose2D truth(0.4, 0.1, 0.02);
	const Points patch = makePatch(w, truth, 10, rng, 5.0);
	// The window covers the copies of the patch 3 m before and after the truth.
	// The exact rival (exhaustive search) is the next door, nearly as good as the truth.
	const auto ex = corr.correlateExhaustive(map, patch, truth, 3.5, 0.05);
	ASSERT_TRUE(ex.has_value());
	ASSERT_EQ(ex->clusterPeaks.size(), 2u);
	EXPECT_LT(ex->ambiguity, 1.05);
	const double shift = std::abs(ex->clusterPeaks[1].patchInMap.x - ex->patchInMap.x);
	EXPECT_NEAR(shift, 3.0, 0.1) << "the rival is the next door";
	// Branch and bound stops at the first rival that fails the filter: the same verdict.
	const auto r = corr.correlate(map, patch, truth, 3.5, 0.05);
	ASSERT_TRUE(r.has_value());
	ASSERT_EQ(r->clusterPeaks.size(), 2u);
	EXPECT_LT(r->ambiguity, prm.min_ambiguity);
	const auto v = r->checkFilters(prm);
	EXPECT_EQ(v.rejection, Reason::Ambiguous) << v.message();
	// With a window too small to hold a copy, the same patch is unambiguous and accepted.
	const auto local = corr.correlate(map, patch, truth, 1.0, 0.05);
	ASSERT_TRUE(local.has_value());
	EXPECT_TRUE(local->passesFilters(prm)) << local->checkFilters(prm).message();
	EXPECT_LE(std::abs(local->patchInMap.x - truth.x), 1.5 * prm.resolution_m);
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
