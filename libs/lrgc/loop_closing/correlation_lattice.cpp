/* Step 5's lattices of exact scores (correlation_search.h, scoreLattice): the covariance of a
 * loop match (pose_grid.cpp, sampledCovariance) weighs the scores S(a, i + u s, j + v s) of a
 * (2n + 1)^2 lattice around the best pose at each sampled heading. Summed point by point: each
 * patch point's lattice cells are read in one go (at stride 1, rows of consecutive bytes),
 * where scoreAt pose by pose would gather over every point once per pose; the integer sums are
 * the same, cells off the grid left out as scoreAt's checked sums leave them.
 */
#include "correlation_search.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace lrgc::detail
{
namespace
{
// The lattice steps u in [0, side) whose cell x + u s lies in [0, limit): [first, last],
// empty when last < first.
struct TStepRange
{
	int first, last;
};
TStepRange stepsInside(int64_t x, int s, int side, int64_t limit)
{
	const int first = x >= 0 ? 0 : static_cast<int>((-x + s - 1) / s);
	const int last = x + int64_t(side - 1) * s < limit ? side - 1
					 : x >= limit                      ? -1
													   : static_cast<int>((limit - 1 - x) / s);
	return {first, std::min(last, side - 1)};
}

// Rows of step 5's lattices (2 kFine + 1 samples, pose_grid.cpp).
constexpr int kFullRow = 9;

// acc[v side + u] += level 0 at lattice cell (u, v) of every point, cells off the grid left
// out (scoreAt's checked sums, transposed: u inner, with s = 1 consecutive bytes).
template <int kUnit>
void accumulateLattice(const TPoseGridProblem& pb, int a, int x0, int y0, int s, int side,
					   uint32_t* acc)
{
	const CCorrelationGrid& g = *pb.grid;
	const uint8_t* data = g.levelData(0);
	const int64_t stride = g.stride();
	const int32_t* c = pb.baseCells.data() + 2 * size_t(a) * size_t(pb.numPoints);
	const int step = kUnit ? 1 : s;
	for (int k = 0; k < pb.numPoints; ++k)
	{
		const int64_t x = int64_t(c[2 * k]) + x0, y = int64_t(c[2 * k + 1]) + y0;
		const TStepRange us = stepsInside(x, s, side, stride);
		const TStepRange vs = stepsInside(y, s, side, g.rows());
		if (us.last < us.first) continue;
		for (int v = vs.first; v <= vs.last; ++v)
		{
			const uint8_t* at =
				data + (y + int64_t(v) * s) * stride + x + int64_t(us.first) * s;
			uint32_t* row = acc + size_t(v) * size_t(side) + size_t(us.first);
			const int count = us.last - us.first + 1;
			if (count == kFullRow)  // the usual row: a count the compiler knows (unrolled)
				for (int u = 0; u < kFullRow; ++u) row[u] += at[u * step];
			else
				for (int u = 0; u < count; ++u) row[u] += at[u * step];
		}
	}
}
}  // namespace

void scoreLattice(const TPoseGridProblem& pb, int a, int i, int j, int s, int n,
				  std::vector<int64_t>& out)
{
	const int side = 2 * n + 1;
	// Per point its lattice cells on the grid, summed in 32 bits (255 N fits).
	std::vector<uint32_t> acc(size_t(side) * size_t(side), 0);
	const int pad = pb.grid->pad();
	const int x0 = i - n * s + pad, y0 = j - n * s + pad;
	if (s == 1)
		accumulateLattice<1>(pb, a, x0, y0, s, side, acc.data());
	else
		accumulateLattice<0>(pb, a, x0, y0, s, side, acc.data());
	out.assign(size_t(side) * size_t(side), 0);
	for (int u = 0; u < side; ++u)
		for (int v = 0; v < side; ++v)
			out[size_t(u) * size_t(side) + size_t(v)] =
				acc[size_t(v) * size_t(side) + size_t(u)];
}
}  // namespace lrgc::detail
