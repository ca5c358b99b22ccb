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
/** Points per partial sum, and per test of the early exit. */
constexpr int kChunk = 64;

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
}  // namespace

// Sum over points of level-h values at base + (i, j), or -1 as soon as the sum cannot reach
// `required` any more.
int64_t boundedSum(const TPoseGridProblem& pb, int h, int a, int i, int j, int64_t required)
{
	const CCorrelationGrid& g = *pb.grid;
	const uint8_t* data = g.levelData(h);
	const int dx = i + g.pad(), dy = j + g.pad();
	const size_t first = size_t(a) * size_t(pb.numPoints);
	int64_t sum = 0;
	if (gatherFits(pb, a, dx, dy))
	{  // every lookup is in range: a plain gather
		const int32_t* lin = pb.linear.data() + first;
		const uint8_t* base = data + int64_t(dy) * g.stride() + dx;
		for (int k0 = 0; k0 < pb.numPoints; k0 += kChunk)
		{
			const int k1 = std::min(pb.numPoints, k0 + kChunk);
			uint32_t part = 0;
			for (int k = k0; k < k1; ++k) part += base[lin[k]];
			sum += part;
			if (sum + int64_t(255) * (pb.numPoints - k1) < required) return -1;
		}
		return sum;
	}
	const unsigned stride = static_cast<unsigned>(g.stride());
	const unsigned rows = static_cast<unsigned>(g.rows());
	const int32_t* c = pb.baseCells.data() + 2 * first;
	for (int k0 = 0; k0 < pb.numPoints; k0 += kChunk)
	{
		const int k1 = std::min(pb.numPoints, k0 + kChunk);
		uint32_t part = 0;
		for (int k = k0; k < k1; ++k)
		{
			const unsigned ux = static_cast<unsigned>(c[2 * k] + dx);
			const unsigned uy = static_cast<unsigned>(c[2 * k + 1] + dy);
			if (ux < stride && uy < rows) part += data[size_t(uy) * stride + ux];
		}
		sum += part;
		if (sum + int64_t(255) * (pb.numPoints - k1) < required) return -1;
	}
	return sum;
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
				 const int64_t* required, int64_t* out)
{
	const CCorrelationGrid& g = *pb.grid;
	const uint8_t* base[4] = {};
	int node[4] = {};  // the node in each lane
	int lanes = 0;
	for (int c = 0; c < n; ++c)
	{
		const int dx = i[c] + g.pad(), dy = j[c] + g.pad();
		if (!gatherFits(pb, a, dx, dy))
		{
			out[c] = boundedSum(pb, h, a, i[c], j[c], required[c]);
			continue;
		}
		base[lanes] = g.levelData(h) + int64_t(dy) * g.stride() + dx;
		node[lanes++] = c;
	}
	for (int l = lanes; l < 4; ++l) base[l] = base[0];  // spare lanes re-read lane 0
	const int32_t* lin = pb.linear.data() + size_t(a) * size_t(pb.numPoints);
	int64_t sum[4] = {0, 0, 0, 0};
	bool alive[4] = {};
	for (int l = 0; l < lanes; ++l) alive[l] = true;
	int numAlive = lanes;
	for (int k0 = 0; k0 < pb.numPoints && numAlive > 0; k0 += kChunk)
	{
		const int k1 = std::min(pb.numPoints, k0 + kChunk);
		uint32_t part[4] = {0, 0, 0, 0};
		for (int k = k0; k < k1; ++k)
		{
			const int32_t o = lin[k];
			part[0] += base[0][o], part[1] += base[1][o];
			part[2] += base[2][o], part[3] += base[3][o];
		}
		const int64_t toCome = int64_t(255) * (pb.numPoints - k1);
		for (int l = 0; l < lanes; ++l)
		{
			if (!alive[l]) continue;
			sum[l] += part[l];
			if (sum[l] + toCome < required[node[l]]) alive[l] = false, --numAlive;
		}
	}
	for (int l = 0; l < lanes; ++l) out[node[l]] = alive[l] ? sum[l] : -1;
}

int64_t blockBound(const TPoseGridProblem& pb, int a0, int a1, int h, int i0, int j0,
				   int64_t required)
{
	const TBoundLookup at = boundLookup(pb, a0, a1, h, i0, j0);
	if (at.trivial) return int64_t(255) * pb.numPoints;
	return boundedSum(pb, at.level, at.a, at.i, at.j, required);
}

int64_t scoreAt(const TPoseGridProblem& pb, int level, int a, int i, int j)
{
	return boundedSum(pb, level, a, i, j, std::numeric_limits<int64_t>::min());
}

}  // namespace lrgc::detail
