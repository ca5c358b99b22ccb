/* Internal to lrgc (not installed): the two searches over the correlation pose grid
 * (correlation_search.cpp) and their bounds (correlation_bounds.cpp).
 *
 * A pose of the grid is (a, i, j): heading theta_a, translation t_c + (i, j) res. Point k of
 * the patch, rotated by theta_a and moved by t_c, falls in cell base_ak; at (a, i, j) it
 * falls in base_ak + (i, j). Integer score S(a, i, j) = sum_k P_0(base_ak + (i, j)) in
 * [0, 255 N]. Both searches return, among poses with S >= floor outside an optional
 * exclusion zone, the one with the largest S and, among equal S, the smallest linear index
 * (a, i, j) -- so the branch and bound result is bit-identical to the exhaustive one.
 */
#pragma once

#include <lrgc/common/StopToken.h>
#include <lrgc/loop_closing/CorrelationGrid.h>

#include <cstdint>
#include <functional>
#include <vector>

namespace lrgc::detail
{
struct TPoseGridProblem
{
	const CCorrelationGrid* grid = nullptr;
	int numPoints = 0;  //!< N
	int halfCells = 0;  //!< W: i, j in [-W, W]
	int numAngles = 0;
	/** Largest distance [cells] a patch point moves per heading step (max |p| dtheta / res);
	 * bounds of heading blocks rely on it; < 0: unknown, heading blocks get no bound. */
	double cellsPerAngleStep = -1;
	/** base cells, numAngles x N pairs (cx, cy), angle-major. */
	std::vector<int32_t> baseCells;
	/** Filled by prepare(): per angle the bounding box of its base cells (minX, maxX, minY,
	 * maxY), and the row-major offsets cy * stride + cx of every base cell (the same at all
	 * levels), so that blocks whose lookups all fall inside the grid need no bound checks. */
	std::vector<int32_t> bbox;
	std::vector<int32_t> linear;
	/** Also reorders each heading's base cells (interleavePoints): every score is a sum over
	 * the points, the same in any order. */
	void prepare();
	/** Each heading's points in the order 0, s, 2s, ..., 1, 1 + s, ... (s = kInterleave), so
	 * that a bound's first chunks sample the whole patch, not one wall: a node that cannot
	 * reach the required score is abandoned after fewer points. */
	void interleavePoints();
	static constexpr int kInterleave = 8;
	/** Translations the search may take, as a pyramid over the side() x side() translations
	 * (row (i + W), column (j + W)): allowed[h] is non-zero where some translation of the
	 * block [i, i + 2^h) x [j, j + 2^h) is allowed (setAllowed). Empty: every translation. */
	std::vector<std::vector<uint8_t>> allowed;
	/** Sets `allowed` from level 0 (side() x side(), non-zero: allowed), up to `levels`
	 * levels. */
	void setAllowed(std::vector<uint8_t> level0, int levels);
	bool blockAllowed(int h, int i0, int j0) const
	{
		return allowed.empty() || allowed[size_t(h)][size_t(i0 + halfCells) * size_t(side()) +
													 size_t(j0 + halfCells)] != 0;
	}
	/** If set, the branch and bound calls it after every kProgressEvaluations evaluations
	 * (progress for the loop-closing worker's schedule). */
	std::function<void()> onEvaluations;
	static constexpr size_t kProgressEvaluations = 4096;
	/** Read as often (by the exhaustive search once per heading): once it is stopped, the
	 * search ends with TSearchHit::stopped. */
	CStopToken stop;

	int side() const { return 2 * halfCells + 1; }
	int64_t linearIndex(int a, int i, int j) const
	{
		return (int64_t(a) * side() + (i + halfCells)) * side() + (j + halfCells);
	}
};

/** One excluded cluster: the poses with inAngle[a] and (i-ci)^2 + (j-cj)^2 <= r2. */
struct TExclusionDisc
{
	std::vector<bool> inAngle;
	int ci = 0, cj = 0;
	double r2 = -1;  //!< squared radius [cells^2]

	bool excludes(int a, int i, int j) const
	{
		if (!inAngle[size_t(a)]) return false;
		const double di = i - ci, dj = j - cj;
		return di * di + dj * dj <= r2;
	}
	/** True if every pose of the block [i0, i1] x [j0, j1] at angle a is excluded. */
	bool excludesBlock(int a, int i0, int i1, int j0, int j1) const
	{
		return excludes(a, i0, j0) && excludes(a, i0, j1) && excludes(a, i1, j0) &&
			   excludes(a, i1, j1);  // the disc is convex
	}
};

/** Poses excluded from a search: those in any of the discs (none: no exclusion). A block is
 * skipped whole only when one disc covers it; a block that several discs cover together is
 * still explored, and each of its poses excluded on its own (exact either way). */
struct TExclusionZone
{
	std::vector<TExclusionDisc> discs;

	bool excludes(int a, int i, int j) const
	{
		for (const auto& d : discs)
			if (d.excludes(a, i, j)) return true;
		return false;
	}
	bool excludesBlock(int a, int i0, int i1, int j0, int j1) const
	{
		for (const auto& d : discs)
			if (d.excludesBlock(a, i0, i1, j0, j1)) return true;
		return false;
	}
};

struct TSearchHit
{
	bool found = false;
	int a = 0, i = 0, j = 0;
	int64_t score = 0;       //!< S in [0, 255 N]
	size_t evaluations = 0;  //!< scores + bounds computed
	bool stopped = false;    //!< ended by a stop request: the hit is not the search's answer
};

/** S(a, i, j) at pyramid level h (h = 0: the exact score). */
int64_t scoreAt(const TPoseGridProblem& pb, int level, int a, int i, int j);

/** A node's bound chunk by chunk: chunk c is the sum over the points [64 c, 64 c + 64) (each
 * heading's points in the same order, so a chunk holds the same points at every heading). Each
 * term bounds what its point adds at any pose of the node, so each chunk bounds what its points
 * add together there; a child's poses are among its parent's, so the parent's chunks bound the
 * child's chunks too, and sum_c min(child_c, parent_c) bounds every score of the child. A
 * child's sum is abandoned once its chunks so far (each the smaller of the two) plus the
 * parent's chunks still to come fall below the score it must reach, instead of 255 a point
 * still to come. A child kept keeps its own sum as its bound. Where each parent chunk is at
 * least the child's (a translation split: level h + 1 covers the child's block) the same
 * children are dropped, only sooner; under a heading block's parent the min can be smaller and
 * drop a child the plain sum would keep, but only one none of whose poses reaches the required
 * score: the best pose is the same either way. */
constexpr int kBoundChunk = 64;
struct TChunkCap
{
	const uint16_t* parent = nullptr;  //!< the parent's chunks; null: 255 a point
	int64_t parentTotal = 0;           //!< their sum
};
/** Receives a node's chunks (each the smaller of its own and the parent's), for its children.
 */
struct TChunkRecord
{
	uint16_t* chunks = nullptr;  //!< null: not recorded
	int64_t total = 0;           //!< out: their sum
};

/** S_h(a, i, j), or -1 as soon as it is known to be below `required` (the sum so far plus 255
 * a point still to come, or the parent's chunks still to come: TChunkCap). Needs prepare(). */
int64_t boundedSum(const TPoseGridProblem& pb, int h, int a, int i, int j, int64_t required,
				   const TChunkCap& cap = {}, TChunkRecord* record = nullptr);

/** What the bound of a node spanning headings [a0, a1] reads: for one heading, level h at
 * (i0, j0). For several, at any heading of the block a patch point lies within M = ceil(c d)
 * cells of where it lies at the middle heading am (c: cells the farthest point moves per
 * heading step, d = max(am - a0, a1 - am); the chord is at most the arc). So every score of the
 * node is at most the sum over points of the max over the (2^h + 2M)-cell square at
 * base_am + (i0 - M, j0 - M): one lookup in level H, 2^H >= 2^h + 2M. Without such a level,
 * or with c unknown: `trivial`, the bound 255 N. */
struct TBoundLookup
{
	bool trivial = false;
	int level = 0, a = 0, i = 0, j = 0;
};
TBoundLookup boundLookup(const TPoseGridProblem& pb, int a0, int a1, int h, int i0, int j0);

/** The exact scores S(a, i + u s, j + v s) of the (2n + 1)^2 lattice |u|, |v| <= n around
 * (i, j) at heading a, in out[(u + n) (2n + 1) + (v + n)]: the same sums as scoreAt pose by
 * pose, taken point by point (each point's lattice cells read in one go, not one gather over
 * every point per pose). Reads pb's grid, numPoints and baseCells only (prepare() not
 * needed). Step 5's covariance samples such lattices. */
void scoreLattice(const TPoseGridProblem& pb, int a, int i, int j, int s, int n,
				  std::vector<int64_t>& out);

/** The sums S_h(a, i[c], j[c]) of n <= 4 nodes that read one level h at one heading a (the
 * children of one split, a few cells apart), in one pass over the points: out[c] is the sum,
 * or -1 if it is below required[c] (found out as soon as the sum so far plus 255 a point still
 * to come is, or the parent's chunks still to come: `cap`, their one parent's), the values of
 * n separate bounds; records[c] (if given) receives node c's chunks. Needs prepare(). */
void siblingSums(const TPoseGridProblem& pb, int h, int a, int n, const int* i, const int* j,
				 const int64_t* required, int64_t* out, const TChunkCap& cap = {},
				 TChunkRecord* records = nullptr);

/** Upper bound of S over headings [a0, a1] x translations [i0, i0 + 2^h) x [j0, j0 + 2^h),
 * or -1 once it is known to be below `required`; `record` (if given) receives its chunks, or
 * its `chunks` is set null where the bound is the trivial 255 N. */
int64_t blockBound(const TPoseGridProblem& pb, int a0, int a1, int h, int i0, int j0,
				   int64_t required, TChunkRecord* record = nullptr);

TSearchHit searchExhaustive(const TPoseGridProblem& pb, int64_t floorScore,
							const TExclusionZone& zone);
/** `firstHit`: return the first pose found with S >= floor (not the best one); for the
 * ambiguity filter's rival, where only whether one exists decides. */
TSearchHit searchBranchAndBound(const TPoseGridProblem& pb, int64_t floorScore,
								const TExclusionZone& zone, bool firstHit = false);

/** Called with each peak searchPeaks() finds; it adds the peak's cluster to the zone. */
using TOnPeak = std::function<void(const TSearchHit&)>;
struct TSearchPeaks
{
	std::vector<TSearchHit> peaks;  //!< best first; empty when stopped
	size_t evaluations = 0;         //!< scores + bounds computed by the whole pass
	bool stopped = false;           //!< ended by a stop request: no peaks
};
/** The k best distinct poses, best first, in one best-first pass over the same nodes: peak n
 * is the best pose scoring at least `floorScore` outside `zone`, which onPeak grows by the
 * cluster of each peak found (so `zone` is the caller's, alive and growing); after peak 1 the
 * floor rises to shareOfBest times its score. Exact: the same peaks as the exhaustive search
 * run again and again with the clusters excluded. */
TSearchPeaks searchPeaks(const TPoseGridProblem& pb, int64_t floorScore, double shareOfBest,
						 size_t k, const TExclusionZone& zone, const TOnPeak& onPeak);

}  // namespace lrgc::detail
