/* The pose-grid problem's set-up (TPoseGridProblem, correlation_search.h): per heading the
 * bounding box of its base cells, the points interleaved for the bound's early exit, their
 * int32 offsets into the grid, and the pyramid of allowed translation blocks. The searches
 * themselves are in correlation_search.cpp.
 */
#include "correlation_search.h"

#include <algorithm>
#include <limits>

namespace lrgc::detail
{
void TPoseGridProblem::prepare()
{
	bbox.assign(4 * size_t(numAngles), 0);
	for (int a = 0; a < numAngles; ++a)
	{
		const int32_t* c = baseCells.data() + 2 * size_t(a) * size_t(numPoints);
		int32_t* b = bbox.data() + 4 * size_t(a);
		b[0] = b[1] = c[0], b[2] = b[3] = c[1];
		for (int k = 1; k < numPoints; ++k)
		{
			b[0] = std::min(b[0], c[2 * k]), b[1] = std::max(b[1], c[2 * k]);
			b[2] = std::min(b[2], c[2 * k + 1]), b[3] = std::max(b[3], c[2 * k + 1]);
		}
	}
	interleavePoints();
	const int64_t stride = grid->stride();
	// int32 offsets: half the index stream of the gather. An offset beyond int32 (a patch
	// far outside a huge grid) leaves `linear` empty, and every sum takes the checked path.
	linear.resize(size_t(numAngles) * size_t(numPoints));
	for (size_t k = 0; k < linear.size(); ++k)
	{
		const int64_t v = int64_t(baseCells[2 * k + 1]) * stride + baseCells[2 * k];
		if (v < std::numeric_limits<int32_t>::min() || v > std::numeric_limits<int32_t>::max())
		{
			linear.clear();
			return;
		}
		linear[k] = static_cast<int32_t>(v);
	}
}

void TPoseGridProblem::interleavePoints()
{
	if (numPoints <= kInterleave) return;
	std::vector<int32_t> block(2 * size_t(numPoints));
	for (int a = 0; a < numAngles; ++a)
	{
		int32_t* c = baseCells.data() + 2 * size_t(a) * size_t(numPoints);
		size_t n = 0;
		for (int r = 0; r < kInterleave; ++r)
			for (int k = r; k < numPoints; k += kInterleave)
				block[n++] = c[2 * k], block[n++] = c[2 * k + 1];
		std::copy(block.begin(), block.end(), c);
	}
}

// Level h from h - 1 (s = 2^(h-1)): a block of 2^h is allowed when one of its four blocks of
// 2^(h-1) at (i, j), (i + s, j), (i, j + s), (i + s, j + s) is (beyond the side: none).
void TPoseGridProblem::setAllowed(std::vector<uint8_t> level0, int levels)
{
	const size_t n = size_t(side());
	allowed.assign(1, std::move(level0));
	for (int h = 1; h < levels; ++h)
	{
		const std::vector<uint8_t>& prev = allowed.back();
		std::vector<uint8_t> next(prev);
		const size_t s = size_t(1) << (h - 1);
		for (size_t r = 0; r < n; ++r)
			for (size_t c = 0; c < n; ++c)
			{
				uint8_t v = prev[r * n + c];
				if (c + s < n) v |= prev[r * n + c + s];
				if (r + s < n) v |= prev[(r + s) * n + c];
				if (r + s < n && c + s < n) v |= prev[(r + s) * n + c + s];
				next[r * n + c] = v;
			}
		allowed.push_back(std::move(next));
	}
}

}  // namespace lrgc::detail
