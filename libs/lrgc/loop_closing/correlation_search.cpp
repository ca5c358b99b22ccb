/* Exhaustive and branch-and-bound searches over the correlation pose grid.
 *
 * Branch and bound (after Olson 2009 and Hess et al. 2016, adapted to the LRGC operator): a
 * node (a0..a1, h, i0, j0) stands for the headings [a0, a1] and the translations
 * [i0, i0 + 2^h) x [j0, j0 + 2^h) clipped to the window. For one heading a its bound
 *     B = sum_k P_h(base_ak + (i0, j0)),  P_h = max of P_0 over a 2^h x 2^h block,
 * is >= S(a, i, j) for every (i, j) of the node, since each term dominates the corresponding
 * term of S. A range of headings (top nodes span 2^top of them, split in halves on the way
 * down together with the translations) is bounded the same way from its middle heading, the
 * block grown by how far a point can move within the range (headingBlockBound): one bound
 * then prunes many headings at once, which a full-circle search needs. Nodes are explored depth
 * first, best bound first; a node is dropped when it cannot beat the best leaf found so far,
 * i.e. B < S_best, or B == S_best and its smallest linear index is larger than the best's. The
 * optimum's ancestors all satisfy B >= S_opt with a smaller or equal index, so none of them is
 * ever dropped: the result is exact. Top-level nodes tile only the translations that put a
 * patch point inside the grid (the rest score 0, below any positive floor), so a window much
 * wider than the old map costs what the map's extent costs. A bound is abandoned early once the
 * partial sum plus 255 per remaining point cannot reach the required value (the node is pruned
 * anyway, and pruned nodes are the majority); depth first, a child's test takes its parent's
 * chunks still to come instead of 255 a point (TChunkCap).
 * Translations outside an allowed region (the far loop search's old path) are pruned block by
 * block from a pyramid of allowed blocks, before any bound. The k best distinct poses
 * (searchPeaks) take the same nodes best-first from a priority queue instead of depth first, so
 * that one pass yields them all. The bounds themselves (one node's, or a split's children's in
 * one pass) are in correlation_bounds.cpp.
 */
#include "correlation_search.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

namespace lrgc::detail
{
namespace
{
constexpr int64_t kNoIndex = std::numeric_limits<int64_t>::max();
/** Heading windows with more headings than this are searched in heading blocks; +-30 deg
 * with a 12 m patch is about 250 headings. */
constexpr int kHeadingBlocksFrom = 256;

struct Best
{
	int64_t score;
	int64_t index = kNoIndex;
	int a = 0, i = 0, j = 0;
	// Can something scoring <= s with index >= idx still beat the best?
	bool beatable(int64_t s, int64_t idx) const
	{
		return s > score || (s == score && idx < index);
	}
	int64_t required(int64_t idx) const { return idx < index ? score : score + 1; }
};

struct Node
{
	int a0, a1, h, i0, j0;  // headings [a0, a1], translations [i0, i0 + 2^h) x [j0, j0 + 2^h)
	int64_t bound;
	int64_t minIndex;
	const uint16_t* chunks = nullptr;  // the bound's chunks (TChunkCap), if recorded
	int64_t chunkTotal = 0;            // their sum
};

class BranchAndBound
{
public:
	BranchAndBound(const TPoseGridProblem& pb, int64_t floorScore, const TExclusionZone& z,
				   bool firstHit)
		: m_pb(pb),
		  m_zone(z),
		  m_firstHit(firstHit),
		  m_numChunks(size_t((pb.numPoints + kBoundChunk - 1) / kBoundChunk))
	{
		m_best.score = floorScore;
	}

	TSearchHit run()
	{
		std::vector<Node> nodes = topNodes(true);
		explore(nodes, 0);
		return hitOf(m_best.a, m_best.i, m_best.j, m_best.score, m_best.index != kNoIndex);
	}

	/* The k best distinct poses in one pass, best first: nodes are taken from a priority
	 * queue, highest bound first (smallest index among equal bounds), so leaves come out in
	 * the exact order of (score desc, index asc); a leaf outside the zone is the next peak
	 * (the best pose outside the clusters of the peaks before it), and `onPeak` grows the zone
	 * by its cluster. After peak 1 the floor rises to shareOfBest times its score. Nodes below
	 * the floor are dropped. */
	TSearchPeaks runPeaks(size_t k, double shareOfBest, const TOnPeak& onPeak)
	{
		const auto lower = [](const Node& x, const Node& y)
		{ return x.bound != y.bound ? x.bound < y.bound : x.minIndex > y.minIndex; };
		std::priority_queue<Node, std::vector<Node>, decltype(lower)> queue(lower,
																			topNodes(false));
		TSearchPeaks out;
		std::vector<TSearchHit>& peaks = out.peaks;
		while (!queue.empty() && peaks.size() < k && !m_done)
		{
			const Node n = queue.top();
			queue.pop();
			if (n.bound < m_best.score) break;  // the floor: no node left reaches it
			if (n.h > 0 || n.a0 != n.a1)
			{
				Children children;
				split(n, children, nullptr);
				for (const Node& c : children) queue.push(c);
				continue;
			}
			if (m_zone.excludes(n.a0, n.i0, n.j0)) continue;
			peaks.push_back(hitOf(n.a0, n.i0, n.j0, n.bound, true));
			onPeak(peaks.back());
			if (peaks.size() == 1)
				m_best.score = std::max(
					m_best.score,
					static_cast<int64_t>(std::ceil(shareOfBest * double(n.bound) - 1e-9)));
		}
		out.evaluations = m_evaluations;
		out.stopped = m_stopped;
		if (m_stopped) peaks.clear();
		return out;
	}

private:
	TSearchHit hitOf(int a, int i, int j, int64_t score, bool found) const
	{
		TSearchHit hit;
		hit.found = found;
		hit.a = a, hit.i = i, hit.j = j;
		hit.score = score;
		hit.evaluations = m_evaluations;
		hit.stopped = m_stopped;
		return hit;
	}

	// The top-level nodes: blocks of 2^top translations and 2^top headings (or fewer, see
	// angleBlock) tiling the translations that put a patch point in the grid, each bounded;
	// with `recordChunks`, each keeps its chunks (its children's cap) in m_topChunks.
	std::vector<Node> topNodes(bool recordChunks)
	{
		const int maxLevel = m_pb.grid->numLevels() - 1;
		// Translation blocks of 2^top cells, heading blocks of 2^top steps; the heading
		// block's bound reads level top + 1 (see headingBlockBound), hence top < maxLevel.
		int top = 0;
		while ((1 << top) < m_pb.side() && top + 1 < maxLevel) ++top;
		std::vector<Node> nodes;
		const int topAngles = angleBlock(top);
		for (int a0 = 0; a0 < m_pb.numAngles; a0 += topAngles)
		{
			const int a1 = std::min(m_pb.numAngles - 1, a0 + topAngles - 1);
			TCellRange r = overlapRange(a0);
			for (int a = a0 + 1; a <= a1; ++a)
			{
				const TCellRange q = overlapRange(a);
				r = {std::min(r.i0, q.i0), std::max(r.i1, q.i1), std::min(r.j0, q.j0),
					 std::max(r.j1, q.j1)};
			}
			for (int i0 = r.i0; i0 <= r.i1; i0 += 1 << top)
				for (int j0 = r.j0; j0 <= r.j1; j0 += 1 << top)
					consider(a0, a1, top, i0, j0, nodes, recordChunks);
		}
		// The pool is complete: point the nodes at their chunks, in order.
		size_t offset = 0;
		for (Node& n : nodes)
			if (n.chunks) n.chunks = m_topChunks.data() + offset, offset += m_numChunks;
		return nodes;
	}

	// Headings per node at translation level h: 2^(h - 2), or 1 when the window has few
	// headings. Measured (tests/large_loop_test.cpp, full circle, +-200 m): one heading per
	// node 39.7 s for the test, 2^(h-2) 19.9 s, 2^h 29.3 s; on the narrow windows of
	// PatchCorrelatorRealLog (+-30 deg at most) heading blocks cost 1.5-2x, hence the
	// threshold. Either way the result is the same (exact).
	int angleBlock(int h) const
	{
		return m_pb.numAngles > kHeadingBlocksFrom ? 1 << std::max(0, h - 2) : 1;
	}
	struct TCellRange
	{
		int i0, i1, j0, j1;
	};
	// Translations at heading a that put at least one patch point in the grid: with the base
	// cells' box [minX, maxX] x [minY, maxY], i in [-maxX, width - 1 - minX] (j likewise). Any
	// other pose scores 0, below a positive floor, so leaving it out keeps the search exact;
	// the cost then follows the old map's extent, not the window's (a window from a large
	// covariance can be hundreds of metres wide). With floor 0 the whole window is kept.
	TCellRange overlapRange(int a) const
	{
		const int W = m_pb.halfCells;
		if (m_best.score <= 0) return {-W, W, -W, W};
		const int32_t* box = m_pb.bbox.data() + 4 * size_t(a);
		const CCorrelationGrid& g = *m_pb.grid;
		return {std::max(-W, -box[1]), std::min(W, g.width() - 1 - box[0]),
				std::max(-W, -box[3]), std::min(W, g.height() - 1 - box[2])};
	}

	bool blockExcluded(int a0, int a1, int i0, int i1, int j0, int j1) const
	{
		for (int a = a0; a <= a1; ++a)
			if (!m_zone.excludesBlock(a, i0, i1, j0, j1)) return false;
		return true;
	}

	// Bounds the top node and appends it to `out` unless it can be pruned already; with
	// `recordChunks` its chunks go to the end of m_topChunks (Node::chunks is set non-null
	// here only as a mark: topNodes points it into the pool once the pool stops growing).
	void consider(int a0, int a1, int h, int i0, int j0, std::vector<Node>& out,
				  bool recordChunks)
	{
		int64_t idx = 0, req = 0;
		if (!admit(a0, a1, h, i0, j0, idx, req)) return;
		const size_t at = m_topChunks.size();
		if (recordChunks) m_topChunks.resize(at + m_numChunks);
		TChunkRecord record{recordChunks ? m_topChunks.data() + at : nullptr};
		const int64_t b = blockBound(m_pb, a0, a1, h, i0, j0, req, &record);
		if (b < 0 || !record.chunks) m_topChunks.resize(at);
		if (b >= 0) out.push_back({a0, a1, h, i0, j0, b, idx, record.chunks, record.total});
	}

	// The checks before a node's bound: false if it can be pruned without one (a block not
	// allowed or excluded, or a score it must reach above 255 N); else counts the evaluation
	// and gives the node's smallest index and the score its bound must reach.
	bool admit(int a0, int a1, int h, int i0, int j0, int64_t& idx, int64_t& req)
	{
		const int W = m_pb.halfCells;
		const int i1 = std::min(W, i0 + (1 << h) - 1), j1 = std::min(W, j0 + (1 << h) - 1);
		if (!m_pb.blockAllowed(h, i0, j0) || blockExcluded(a0, a1, i0, i1, j0, j1))
			return false;
		idx = m_pb.linearIndex(a0, i0, j0);  // the block's smallest index
		if (m_best.required(idx) > int64_t(255) * m_pb.numPoints) return false;
		if (++m_evaluations % TPoseGridProblem::kProgressEvaluations == 0)
		{
			if (m_pb.onEvaluations) m_pb.onEvaluations();
			if (m_pb.stop.stopRequested()) m_done = m_stopped = true;
		}
		req = m_best.required(idx);
		return true;
	}

	struct Children
	{
		Node items[8];
		size_t count = 0;
		void push_back(const Node& n) { items[count++] = n; }
		Node* begin() { return items; }
		Node* end() { return items + count; }
	};

	// Depth first, best bound first; the children of a node explored at `depth` keep their
	// chunks in m_depthChunks[depth + 1] (8 slots), free again once they are explored.
	template <class Nodes>
	void explore(Nodes& nodes, size_t depth)
	{
		std::sort(nodes.begin(), nodes.end(),
				  [](const Node& x, const Node& y)
				  { return x.bound != y.bound ? x.bound > y.bound : x.minIndex < y.minIndex; });
		if (m_depthChunks.size() < depth + 2)
			m_depthChunks.resize(depth + 2, std::vector<uint16_t>(8 * m_numChunks));
		for (const Node& n : nodes)
		{
			if (m_done) return;
			if (n.bound < m_best.score) break;  // sorted: no later node can beat it either
			if (!m_best.beatable(n.bound, n.minIndex)) continue;
			if (n.h == 0 && n.a0 == n.a1)
			{
				if (m_zone.excludes(n.a0, n.i0, n.j0)) continue;
				m_best.score = n.bound, m_best.index = n.minIndex;
				m_best.a = n.a0, m_best.i = n.i0, m_best.j = n.j0;
				m_done = m_firstHit;
				continue;
			}
			Children children;
			split(n, children, m_depthChunks[depth + 1].data());
			explore(children, depth + 1);
		}
	}

	// The children of a node, each bounded (those that can be pruned already left out):
	// the heading range and the translation block halved, whichever is not single. The (up
	// to four) translations of one heading range read one level at one heading: bounded in
	// one pass (siblingSums), each capped by the node's chunks (TChunkCap). `slots` (8 of
	// m_numChunks, or null) receive the children's chunks.
	void split(const Node& n, Children& children, uint16_t* slots)
	{
		const TChunkCap cap{n.chunks, n.chunkTotal};
		const int W = m_pb.halfCells;
		const int h = n.h > 0 ? n.h - 1 : 0;
		const int half = n.h > 0 ? 1 << h : 1;
		const int span = n.a1 - n.a0 + 1;
		const bool splitA = span > 1 && (n.h == 0 || span > angleBlock(h));
		const int aSplit = splitA ? n.a0 + span / 2 : n.a1 + 1;
		for (int part = 0; part < 2; ++part)
		{
			const int ca0 = part == 0 ? n.a0 : aSplit, ca1 = part == 0 ? aSplit - 1 : n.a1;
			if (ca0 > ca1) continue;
			int ci[4], cj[4], m = 0;
			int64_t idx[4], req[4], bound[4];
			for (int di = 0; di < (n.h > 0 ? 2 : 1); ++di)
				for (int dj = 0; dj < (n.h > 0 ? 2 : 1); ++dj)
				{
					ci[m] = n.i0 + di * half, cj[m] = n.j0 + dj * half;
					if (ci[m] <= W && cj[m] <= W &&
						admit(ca0, ca1, h, ci[m], cj[m], idx[m], req[m]))
						++m;
				}
			if (m == 0) continue;
			// A leaf has no children to cap: its chunks are not kept.
			const bool keep = slots && (h > 0 || ca0 != ca1);
			TChunkRecord rec[4];
			for (int c = 0; c < m; ++c)
				rec[c].chunks = keep ? slots + size_t(4 * part + c) * m_numChunks : nullptr;
			const TBoundLookup at = boundLookup(m_pb, ca0, ca1, h, ci[0], cj[0]);
			if (at.trivial)
			{
				std::fill(bound, bound + m, int64_t(255) * m_pb.numPoints);
				for (int c = 0; c < m; ++c) rec[c].chunks = nullptr;
			}
			else if (m == 1)
				bound[0] = boundedSum(m_pb, at.level, at.a, at.i, at.j, req[0], cap, rec);
			else
			{
				int li[4], lj[4];  // the same shift for every child
				for (int c = 0; c < m; ++c)
					li[c] = at.i + ci[c] - ci[0], lj[c] = at.j + cj[c] - cj[0];
				siblingSums(m_pb, at.level, at.a, m, li, lj, req, bound, cap, rec);
			}
			for (int c = 0; c < m; ++c)
				if (bound[c] >= 0)
					children.push_back({ca0, ca1, h, ci[c], cj[c], bound[c], idx[c],
										rec[c].chunks, rec[c].total});
		}
	}

	const TPoseGridProblem& m_pb;
	const TExclusionZone& m_zone;
	bool m_firstHit = false;  // stop at the first pose reaching the floor
	bool m_done = false;
	bool m_stopped = false;  // ended by pb.stop
	Best m_best{};
	size_t m_evaluations = 0;
	size_t m_numChunks;                                // chunks of a node's bound
	std::vector<uint16_t> m_topChunks;                 // the top nodes' chunks
	std::vector<std::vector<uint16_t>> m_depthChunks;  // per depth, 8 children's chunks
};
}  // namespace

TSearchHit searchExhaustive(const TPoseGridProblem& pb, int64_t floorScore,
							const TExclusionZone& zone)
{
	const int W = pb.halfCells;
	Best best{};
	best.score = floorScore;
	size_t evaluations = 0;
	TSearchHit hit;
	for (int a = 0; a < pb.numAngles; ++a)
	{
		if (pb.stop.stopRequested())
		{
			hit.stopped = true;
			break;
		}
		for (int i = -W; i <= W; ++i)
			for (int j = -W; j <= W; ++j)
			{
				if (!pb.blockAllowed(0, i, j) || zone.excludes(a, i, j)) continue;
				++evaluations;
				const int64_t s = scoreAt(pb, 0, a, i, j);
				const int64_t idx = pb.linearIndex(a, i, j);
				if (best.beatable(s, idx)) best = {s, idx, a, i, j};
			}
	}
	hit.found = best.index != kNoIndex;
	hit.a = best.a, hit.i = best.i, hit.j = best.j;
	hit.score = best.score;
	hit.evaluations = evaluations;
	return hit;
}

TSearchHit searchBranchAndBound(const TPoseGridProblem& pb, int64_t floorScore,
								const TExclusionZone& zone, bool firstHit)
{
	return BranchAndBound(pb, floorScore, zone, firstHit).run();
}

TSearchPeaks searchPeaks(const TPoseGridProblem& pb, int64_t floorScore, double shareOfBest,
						 size_t k, const TExclusionZone& zone, const TOnPeak& onPeak)
{
	return BranchAndBound(pb, floorScore, zone, false).runPeaks(k, shareOfBest, onPeak);
}

}  // namespace lrgc::detail
