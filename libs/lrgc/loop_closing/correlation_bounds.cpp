/* The bounds of the pose-grid searches (correlation_search.h): a node's bound is one sum
 * over the patch points of a pyramid level's values, S_h(a, i, j) = sum_k P_h(base_ak + (i, j))
 * in [0, 255 N], abandoned (-1) as soon as it cannot reach the score the node must reach; a
 * heading block's bound reads a coarser level at its middle heading (boundLookup). The sums
 * are gathers from the pyramid, bound by their cache misses: the (up to four) translation
 * children of a split are summed in one pass (siblingSums), their lookups sharing lines. The
 * searches themselves are in correlation_search.cpp.
 */
#include "correlation_search.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lrgc::detail
{
namespace
{
// Whether every lookup of heading a at (dx, dy) from the padded origin falls inside the grid,
// so that the sum can gather through the row-major offsets without bound checks.
bool gatherFits(const TPoseGridProblem& pb, int a, int dx, int dy)
{
	const CCorrelationGrid& g = *pb.grid;
	const int32_t* box = pb.bbox.data() + 4 * size_t(a);
	return !pb.linear.empty() && box[0] + dx >= 0 && box[1] + dx < g.stride() &&
		   box[2] + dy >= 0 && box[3] + dy < g.rows();
}

int ceilLog2(int64_t v)
{
	int k = 0;
	while ((int64_t(1) << k) < v) ++k;
	return k;
}

/** One node's sum chunk by chunk, with its early exit (TChunkCap): without a parent's chunks
 * the test is the sum so far plus 255 a point still to come. */
class CChunkedSum
{
public:
	CChunkedSum(const TChunkCap& cap, int numPoints)
		: m_parent(cap.parent),
		  m_toCome(cap.parent ? cap.parentTotal : int64_t(255) * numPoints)
	{
	}
	/** Adds chunk c (`points` points summing to `part`); false once the node's poses cannot
	 * reach `required`. */
	bool add(int c, int points, uint32_t part, int64_t required, TChunkRecord* record)
	{
		m_sum += part;
		uint32_t capped = part;
		if (m_parent)
			capped = std::min<uint32_t>(part, m_parent[c]), m_toCome -= m_parent[c];
		else
			m_toCome -= int64_t(255) * points;
		m_capped += capped;
		if (record && record->chunks) record->chunks[c] = static_cast<uint16_t>(capped);
		return m_capped + m_toCome >= required;
	}
	/** The node's own sum (its bound); records the chunks' total. */
	int64_t finish(TChunkRecord* record) const
	{
		if (record) record->total = m_capped;
		return m_sum;
	}

private:
	const uint16_t* m_parent;
	int64_t m_toCome;
	int64_t m_sum = 0, m_capped = 0;
};
}  // namespace

// Sum over points of level-h values at base + (i, j), or -1 as soon as the sum cannot reach
// `required` any more (CChunkedSum).
int64_t boundedSum(const TPoseGridProblem& pb, int h, int a, int i, int j, int64_t required,
				   const TChunkCap& cap, TChunkRecord* record)
{
	const CCorrelationGrid& g = *pb.grid;
	const uint8_t* data = g.levelData(h);
	const int dx = i + g.pad(), dy = j + g.pad();
	const size_t first = size_t(a) * size_t(pb.numPoints);
	CChunkedSum sum(cap, pb.numPoints);
	if (gatherFits(pb, a, dx, dy))
	{  // every lookup is in range: a plain gather
		const int32_t* lin = pb.linear.data() + first;
		const uint8_t* base = data + int64_t(dy) * g.stride() + dx;
		for (int k0 = 0, c = 0; k0 < pb.numPoints; k0 += kBoundChunk, ++c)
		{
			const int k1 = std::min(pb.numPoints, k0 + kBoundChunk);
			uint32_t part = 0;
			for (int k = k0; k < k1; ++k) part += base[lin[k]];
			if (!sum.add(c, k1 - k0, part, required, record)) return -1;
		}
		return sum.finish(record);
	}
	const unsigned stride = static_cast<unsigned>(g.stride());
	const unsigned rows = static_cast<unsigned>(g.rows());
	const int32_t* cells = pb.baseCells.data() + 2 * first;
	for (int k0 = 0, c = 0; k0 < pb.numPoints; k0 += kBoundChunk, ++c)
	{
		const int k1 = std::min(pb.numPoints, k0 + kBoundChunk);
		uint32_t part = 0;
		for (int k = k0; k < k1; ++k)
		{
			const unsigned ux = static_cast<unsigned>(cells[2 * k] + dx);
			const unsigned uy = static_cast<unsigned>(cells[2 * k + 1] + dy);
			if (ux < stride && uy < rows) part += data[size_t(uy) * stride + ux];
		}
		if (!sum.add(c, k1 - k0, part, required, record)) return -1;
	}
	return sum.finish(record);
}

TBoundLookup boundLookup(const TPoseGridProblem& pb, int a0, int a1, int h, int i0, int j0)
{
	if (a0 == a1) return {false, h, a0, i0, j0};
	if (pb.cellsPerAngleStep < 0) return {true};
	const int am = a0 + (a1 - a0) / 2;
	const int d = std::max(am - a0, a1 - am);
	const int M = static_cast<int>(std::ceil(pb.cellsPerAngleStep * d + 1e-6));
	const int H = ceilLog2((int64_t(1) << h) + 2 * int64_t(M));
	if (H > pb.grid->numLevels() - 1) return {true};
	return {false, H, am, i0 - M, j0 - M};
}

// The n lookups of a point share cache lines: fetched once for all n nodes instead of once
// per node (the sums are bound by those fetches, not by the additions). A node dropped keeps
// its lane, unread.
void siblingSums(const TPoseGridProblem& pb, int h, int a, int n, const int* i, const int* j,
				 const int64_t* required, int64_t* out, const TChunkCap& cap,
				 TChunkRecord* records)
{
	const CCorrelationGrid& g = *pb.grid;
	const uint8_t* base[4] = {};
	int node[4] = {};  // the node in each lane
	int lanes = 0;
	for (int c = 0; c < n; ++c)
	{
		TChunkRecord* record = records ? records + c : nullptr;
		const int dx = i[c] + g.pad(), dy = j[c] + g.pad();
		if (!gatherFits(pb, a, dx, dy))
		{
			out[c] = boundedSum(pb, h, a, i[c], j[c], required[c], cap, record);
			continue;
		}
		base[lanes] = g.levelData(h) + int64_t(dy) * g.stride() + dx;
		node[lanes++] = c;
	}
	for (int l = lanes; l < 4; ++l) base[l] = base[0];  // spare lanes re-read lane 0
	const int32_t* lin = pb.linear.data() + size_t(a) * size_t(pb.numPoints);
	CChunkedSum sum[4] = {
		{cap, pb.numPoints}, {cap, pb.numPoints}, {cap, pb.numPoints}, {cap, pb.numPoints}};
	bool alive[4] = {};
	for (int l = 0; l < lanes; ++l) alive[l] = true;
	int numAlive = lanes;
	for (int k0 = 0, c = 0; k0 < pb.numPoints && numAlive > 0; k0 += kBoundChunk, ++c)
	{
		const int k1 = std::min(pb.numPoints, k0 + kBoundChunk);
		uint32_t part[4] = {0, 0, 0, 0};
		for (int k = k0; k < k1; ++k)
		{
			const int32_t o = lin[k];
			part[0] += base[0][o], part[1] += base[1][o];
			part[2] += base[2][o], part[3] += base[3][o];
		}
		for (int l = 0; l < lanes; ++l)
		{
			if (!alive[l]) continue;
			TChunkRecord* record = records ? records + node[l] : nullptr;
			if (!sum[l].add(c, k1 - k0, part[l], required[node[l]], record))
				alive[l] = false, --numAlive;
		}
	}
	for (int l = 0; l < lanes; ++l)
		out[node[l]] = alive[l] ? sum[l].finish(records ? records + node[l] : nullptr) : -1;
}

int64_t blockBound(const TPoseGridProblem& pb, int a0, int a1, int h, int i0, int j0,
				   int64_t required, TChunkRecord* record)
{
	const TBoundLookup at = boundLookup(pb, a0, a1, h, i0, j0);
	if (at.trivial)
	{
		if (record) record->chunks = nullptr;  // nothing to cap the children with
		return int64_t(255) * pb.numPoints;
	}
	return boundedSum(pb, at.level, at.a, at.i, at.j, required, {}, record);
}

int64_t scoreAt(const TPoseGridProblem& pb, int level, int a, int i, int j)
{
	return boundedSum(pb, level, a, i, j, std::numeric_limits<int64_t>::min());
}

}  // namespace lrgc::detail
