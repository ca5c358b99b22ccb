/* The patch correlator's search core (correlation_search.h) on the synthetic segment worlds
 * of PatchCorrelator_unittest.h: the bound of a block of headings against brute force, and
 * the far search's peaks in one best-first pass against repeated exhaustive searches. */
#include <gtest/gtest.h>

#include <lrgc/loop_closing/PatchCorrelator.h>

#include "PatchCorrelator_unittest.h"
#include "correlation_search.h"
#include "pose_grid.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

using lrgc::CCorrelationGrid;
using lrgc::CPatchCorrelator;
using lrgc::TPatchCorrelatorParams;
using mrpt::math::TPose2D;
using namespace lrgc::test;

namespace
{
/** A pose-grid problem on `map` (grid, numPoints, numAngles and its base cells: map cells,
 * per heading then per point): heading a (0 .. numAngles - 1) turns the patch to
 * robot.phi + (a + a0) dtheta [rad], placed at robot. Not prepared. */
lrgc::detail::TPoseGridProblem problemOf(const CCorrelationGrid& map, const TPose2D& robot,
										 const Points& patch, int numAngles, int a0,
										 double dtheta)
{
	lrgc::detail::TPoseGridProblem pb;
	pb.grid = &map;
	pb.numPoints = int(patch.size());
	pb.numAngles = numAngles;
	for (int a = 0; a < pb.numAngles; ++a)
		lrgc::detail::appendBaseCells(map, patch, robot, robot.phi + (a + a0) * dtheta,
									  pb.baseCells);
	return pb;
}

/** A room of segments (randomWorld: 12 m, 10 segments), its grid by `corr` (its resolution
 * and blur, `margin` [m] around the walls), a robot pose in it and the patch `scans` scans
 * from there see. */
struct TRoomPatch
{
	World world;
	CCorrelationGrid map;
	TPose2D robot;
	Points patch;
};
TRoomPatch roomPatch(std::mt19937& rng, const CPatchCorrelator& corr, double margin, int scans)
{
	std::uniform_real_distribution<double> inRoom(2.5, 9.5), ang(-M_PI, M_PI);
	TRoomPatch r;
	r.world = randomWorld(rng, 12, 10);
	r.map = corr.makeGrid(rasterise(r.world), margin);
	r.robot = TPose2D(inRoom(rng), inRoom(rng), ang(rng));
	r.patch = makePatch(r.world, r.robot, scans, rng);
	return r;
}
}  // namespace

// The bound of a node spanning several headings (branch and bound over the full circle) is at
// least every exact score of its headings and translations: random blocks of a real problem
// (a room seen by 8 scans, 0.05 m cells, the correlator's own heading step).
TEST(PatchCorrelator, HeadingBlockBoundIsAtLeastEveryScoreOfItsBlock)
{
	std::mt19937 rng(99);
	const TRoomPatch room = roomPatch(rng, CPatchCorrelator(), 0.5, 8);
	const CCorrelationGrid& map = room.map;
	const TPose2D& robot = room.robot;
	const Points& patch = room.patch;
	double maxR = 0;
	for (const auto& p : patch) maxR = std::max(maxR, p.norm());
	const double res = map.resolution(), dtheta = res / maxR;
	lrgc::detail::TPoseGridProblem pb = problemOf(map, robot, patch, 200, -100, dtheta);
	pb.halfCells = 40;
	pb.cellsPerAngleStep = maxR * dtheta / res;
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

// Step 5's lattices of scores (detail::scoreLattice, summed point by point) equal scoreAt pose
// by pose: lattices well inside the grid (every lookup in range), at and beyond its edges
// (checked lookups), with unit and wider strides and several sizes.
TEST(PatchCorrelator, ScoreLatticeEqualsScoreAtEveryPose)
{
	std::mt19937 rng(4242);
	const TRoomPatch room = roomPatch(rng, CPatchCorrelator(), 0.5, 8);
	const CCorrelationGrid& map = room.map;
	const TPose2D& robot = room.robot;
	const Points& patch = room.patch;
	lrgc::detail::TPoseGridProblem pb = problemOf(map, robot, patch, 9, -4, 0.01);
	pb.prepare();
	const int far = map.width() + map.height();
	std::uniform_int_distribution<int> angle(0, pb.numAngles - 1), near(-6, 6), wide(-far, far),
		stride(1, 4), half(1, 4);
	int onMap = 0, offMap = 0;
	std::vector<int64_t> lattice;
	for (int trial = 0; trial < 200; ++trial)
	{
		const int a = angle(rng), s = trial % 3 == 0 ? 1 : stride(rng), n = half(rng);
		const bool atEdge = trial % 2 == 1;
		const int i = atEdge ? wide(rng) : near(rng), j = atEdge ? wide(rng) : near(rng);
		lrgc::detail::scoreLattice(pb, a, i, j, s, n, lattice);
		ASSERT_EQ(lattice.size(), size_t((2 * n + 1) * (2 * n + 1)));
		bool allPositive = true;
		for (int u = -n; u <= n; ++u)
			for (int v = -n; v <= n; ++v)
			{
				const int64_t expected = lrgc::detail::scoreAt(pb, 0, a, i + u * s, j + v * s);
				ASSERT_EQ(lattice[size_t((u + n) * (2 * n + 1) + (v + n))], expected)
					<< "heading " << a << ", centre (" << i << ", " << j << "), stride " << s
					<< ", pose (" << u << ", " << v << ")";
				allPositive = allPositive && expected > 0;
			}
		(allPositive ? onMap : offMap) += 1;
	}
	EXPECT_GT(onMap, 50) << "lattices on the map, every score positive";
	EXPECT_GT(offMap, 50) << "lattices partly or wholly off the map";
}

// The far search's peaks in one best-first pass (detail::searchPeaks) are exactly those of
// the exhaustive search run again and again, each time with the clusters of the peaks before
// excluded and, after the first, the floor at 0.6 of its score: with and without a region the
// translations are restricted to (setAllowed), with one heading per node (60 headings) and
// with blocks of headings (300).
TEST(PatchCorrelator, PeaksInOnePassEqualRepeatedExhaustiveSearches)
{
	std::mt19937 rng(777);
	TPatchCorrelatorParams prm;
	prm.resolution_m = 0.2, prm.blur_sigma_m = 0.2;
	const CPatchCorrelator corr(prm);
	for (int trial = 0; trial < 4; ++trial)
	{
		const TRoomPatch room = roomPatch(rng, corr, 0.6, 6);
		const CCorrelationGrid& map = room.map;
		const TPose2D& robot = room.robot;
		const Points& patch = room.patch;
		const int numAngles = trial < 2 ? 60 : 300;
		double maxR = 0;
		for (const auto& p : patch) maxR = std::max(maxR, p.norm());
		const double dtheta = 2 * M_PI / numAngles;
		lrgc::detail::TPoseGridProblem pb = problemOf(map, robot, patch, numAngles, 0, dtheta);
		pb.halfCells = trial < 2 ? 20 : 8;
		pb.cellsPerAngleStep = maxR * dtheta / map.resolution();
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

namespace
{
/** S at level h by the definition: the plain sum over `cells` (one heading's (cx, cy) pairs,
 * in their original order), out-of-grid lookups 0. */
int64_t plainSum(const CCorrelationGrid& g, const std::vector<int32_t>& cells, int h, int i,
				 int j)
{
	int64_t sum = 0;
	for (size_t k = 0; k < cells.size(); k += 2)
	{
		const int64_t x = int64_t(cells[k]) + i + g.pad(),
					  y = int64_t(cells[k + 1]) + j + g.pad();
		if (x >= 0 && x < g.stride() && y >= 0 && y < g.rows())
			sum += g.levelData(h)[y * g.stride() + x];
	}
	return sum;
}
}  // namespace

// prepare() reorders each heading's points (interleaved, so that a bound's first chunks sample
// the whole patch) and keeps int32 offsets: the points of each heading stay the same set, and
// scoreAt at every level equals the plain sum in the original order, inside the grid (the
// unchecked gather) and across its edges. A point whose offset exceeds int32 drops the
// offsets, and the checked path still gives the plain sum.
TEST(PatchCorrelator, ScoreAtAfterReorderingEqualsThePlainSum)
{
	std::mt19937 rng(2024);
	const TRoomPatch room = roomPatch(rng, CPatchCorrelator(), 0.5, 8);
	const CCorrelationGrid& map = room.map;
	for (const bool huge : {false, true})
	{
		lrgc::detail::TPoseGridProblem pb = problemOf(map, room.robot, room.patch, 7, -3, 0.02);
		if (huge) pb.baseCells[1] = 1 << 30;  // heading 0, point 0: far beyond the grid
		const std::vector<int32_t> original = pb.baseCells;
		pb.prepare();
		ASSERT_EQ(pb.linear.empty(), huge);
		ASSERT_GT(pb.numPoints, 2 * lrgc::detail::TPoseGridProblem::kInterleave);
		EXPECT_NE(pb.baseCells, original) << "the points are reordered";
		const size_t n = 2 * size_t(pb.numPoints);
		std::vector<std::vector<int32_t>> heading(size_t(pb.numAngles));
		for (int a = 0; a < pb.numAngles; ++a)
		{
			heading[size_t(a)].assign(original.begin() + a * n, original.begin() + (a + 1) * n);
			using Pair = std::pair<int32_t, int32_t>;
			std::vector<Pair> before, after;
			for (size_t k = 0; k < n; k += 2)
			{
				before.emplace_back(original[a * n + k], original[a * n + k + 1]);
				after.emplace_back(pb.baseCells[a * n + k], pb.baseCells[a * n + k + 1]);
			}
			std::sort(before.begin(), before.end()), std::sort(after.begin(), after.end());
			ASSERT_EQ(before, after) << "heading " << a << ": the same points";
		}
		const int far = map.width() + map.height();
		std::uniform_int_distribution<int> level(0, map.numLevels() - 1),
			angle(0, pb.numAngles - 1), near(-6, 6), wide(-far, far);
		int nonZero = 0;
		for (int trial = 0; trial < 400; ++trial)
		{
			const int h = level(rng), a = angle(rng);
			const int i = trial % 2 ? wide(rng) : near(rng),
					  j = trial % 2 ? wide(rng) : near(rng);
			const int64_t s = lrgc::detail::scoreAt(pb, h, a, i, j);
			ASSERT_EQ(s, plainSum(map, heading[size_t(a)], h, i, j))
				<< "level " << h << ", heading " << a << ", (" << i << ", " << j << ")";
			nonZero += s > 0;
		}
		EXPECT_GT(nonZero, 150);
	}
}

// The children of one split bounded in one pass (siblingSums) give what each would alone:
// the sum at its level, heading and translation when it reaches the score asked of it, -1
// when it does not; on and off the grid (the checked path), with 1 to 4 children.
TEST(PatchCorrelator, SiblingSumsEqualTheSumsOneByOne)
{
	std::mt19937 rng(77);
	const TRoomPatch room = roomPatch(rng, CPatchCorrelator(), 0.5, 8);
	const CCorrelationGrid& map = room.map;
	lrgc::detail::TPoseGridProblem pb = problemOf(map, room.robot, room.patch, 9, -4, 0.02);
	pb.prepare();
	const int far = map.width() + map.height();
	std::uniform_int_distribution<int> level(0, map.numLevels() - 1),
		angle(0, pb.numAngles - 1), count(1, 4), near(-6, 6), wide(-far, far);
	std::uniform_real_distribution<double> share(0.0, 1.0);
	int reached = 0, dropped = 0;
	for (int trial = 0; trial < 600; ++trial)
	{
		const int h = level(rng), a = angle(rng), n = count(rng);
		const int i0 = trial % 3 ? near(rng) : wide(rng),
				  j0 = trial % 3 ? near(rng) : wide(rng);
		const int half = 1 << std::max(0, h - 1);
		int i[4], j[4];
		int64_t required[4], out[4];
		for (int c = 0; c < n; ++c)
		{
			i[c] = i0 + (c / 2) * half, j[c] = j0 + (c % 2) * half;
			if (trial % 7 == 0 && c == n - 1) i[c] = wide(rng), j[c] = wide(rng);  // far apart
			const int64_t s = lrgc::detail::scoreAt(pb, h, a, i[c], j[c]);
			required[c] =
				static_cast<int64_t>(share(rng) * 2 * double(std::max<int64_t>(s, 1)));
		}
		lrgc::detail::siblingSums(pb, h, a, n, i, j, required, out);
		for (int c = 0; c < n; ++c)
		{
			const int64_t s = lrgc::detail::scoreAt(pb, h, a, i[c], j[c]);
			ASSERT_EQ(out[c], s >= required[c] ? s : -1)
				<< "trial " << trial << ", child " << c << " of " << n << ": level " << h
				<< ", heading " << a << ", (" << i[c] << ", " << j[c] << "), required "
				<< required[c];
			(s >= required[c] ? reached : dropped) += 1;
		}
	}
	EXPECT_GT(reached, 200);
	EXPECT_GT(dropped, 200);
}

// A split's children capped by their parent's chunks (TChunkCap): a child is dropped only when
// none of its poses reaches the score asked of it (the best exact score over its 2^h x 2^h
// translations below it), else kept with its own sum, as without the cap; its recorded chunks
// are the smaller of its own and the parent's, chunk by chunk, and bound its every pose. The
// children in one pass (siblingSums) give what each gives alone (boundedSum), records too.
// Two parents: the search's own (the block at level h + 1, whose chunks are each at least the
// children's: the cap only drops sooner, never others), and the tightest a parent can be (each
// chunk the largest exact chunk over the block's poses), which must drop children their own sum
// alone would keep.
TEST(PatchCorrelator, ChildrenCappedByTheirParentsChunksAreDroppedOnlyWhenNoPoseReaches)
{
	namespace d = lrgc::detail;
	std::mt19937 rng(4711);
	const TRoomPatch room = roomPatch(rng, CPatchCorrelator(), 0.5, 8);
	const CCorrelationGrid& map = room.map;
	d::TPoseGridProblem pb = problemOf(map, room.robot, room.patch, 5, -2, 0.02);
	pb.prepare();
	const size_t numChunks = size_t((pb.numPoints + d::kBoundChunk - 1) / d::kBoundChunk);
	ASSERT_GT(numChunks, 3u);
	std::uniform_int_distribution<int> level(0, 3), angle(0, pb.numAngles - 1), near(-8, 8),
		shift(-40, 40);
	const auto chunksOf = [&](int h, int a, int i, int j)
	{
		std::vector<uint16_t> chunks(numChunks);
		d::TChunkRecord rec{chunks.data()};
		d::boundedSum(pb, h, a, i, j, std::numeric_limits<int64_t>::min(), {}, &rec);
		return chunks;
	};
	int kept = 0, dropped = 0, droppedByTheCap = 0;
	for (int trial = 0; trial < 300; ++trial)
	{
		const bool tightest = trial % 2 == 1;
		const int h = level(rng), a = angle(rng), i0 = near(rng), j0 = near(rng);
		const int half = 1 << h;
		std::vector<uint16_t> parent = chunksOf(h + 1, a, i0, j0);
		if (tightest)
		{
			std::fill(parent.begin(), parent.end(), 0);
			for (int u = 0; u < 2 * half; ++u)
				for (int v = 0; v < 2 * half; ++v)
				{
					const std::vector<uint16_t> pose = chunksOf(0, a, i0 + u, j0 + v);
					for (size_t k = 0; k < numChunks; ++k)
						parent[k] = std::max(parent[k], pose[k]);
				}
		}
		int64_t parentTotal = 0;
		for (const uint16_t c : parent) parentTotal += c;
		const d::TChunkCap cap{parent.data(), parentTotal};
		int i[4], j[4];
		int64_t required[4], best[4], out[4], alone[4];
		std::vector<uint16_t> slots(8 * numChunks, 0);
		d::TChunkRecord rec[4], recAlone[4];
		for (int c = 0; c < 4; ++c)
		{
			i[c] = i0 + (c / 2) * half, j[c] = j0 + (c % 2) * half;
			best[c] = 0;
			for (int u = 0; u < half; ++u)
				for (int v = 0; v < half; ++v)
					best[c] = std::max(best[c], d::scoreAt(pb, 0, a, i[c] + u, j[c] + v));
			required[c] =
				std::max<int64_t>(1, best[c] + shift(rng) * int64_t(pb.numPoints) / 8);
			rec[c].chunks = slots.data() + size_t(c) * numChunks;
			recAlone[c].chunks = slots.data() + size_t(4 + c) * numChunks;
			alone[c] = d::boundedSum(pb, h, a, i[c], j[c], required[c], cap, &recAlone[c]);
		}
		d::siblingSums(pb, h, a, 4, i, j, required, out, cap, rec);
		for (int c = 0; c < 4; ++c)
		{
			const auto where = ::testing::Message()
							   << "trial " << trial << ", child " << c << ": level " << h
							   << ", heading " << a << ", (" << i[c] << ", " << j[c]
							   << "), required " << required[c] << ", best " << best[c]
							   << (tightest ? ", tightest parent" : ", level h + 1 parent");
			ASSERT_EQ(out[c], alone[c]) << where;
			const int64_t own = d::scoreAt(pb, h, a, i[c], j[c]);
			if (!tightest)
			{
				ASSERT_EQ(out[c], own >= required[c] ? own : -1) << where;
			}
			if (out[c] < 0)
			{
				ASSERT_LT(best[c], required[c]) << where << ": dropped, yet a pose reaches";
				++dropped, droppedByTheCap += own >= required[c];
				continue;
			}
			++kept;
			ASSERT_EQ(out[c], own) << where;
			const std::vector<uint16_t> mine = chunksOf(h, a, i[c], j[c]);
			int64_t total = 0;
			for (size_t k = 0; k < numChunks; ++k)
			{
				ASSERT_EQ(rec[c].chunks[k], std::min(mine[k], parent[k]))
					<< where << ", chunk " << k;
				ASSERT_EQ(recAlone[c].chunks[k], rec[c].chunks[k]) << where << ", chunk " << k;
				total += rec[c].chunks[k];
			}
			ASSERT_EQ(rec[c].total, total) << where;
			ASSERT_GE(total, best[c]) << where << ": the recorded chunks must bound every pose";
		}
	}
	EXPECT_GT(kept, 200);
	EXPECT_GT(dropped, 200);
	EXPECT_GT(droppedByTheCap, 20)
		<< "the tightest cap must drop children their sum would keep";
}
