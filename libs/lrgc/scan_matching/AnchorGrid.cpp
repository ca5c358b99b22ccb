#include <lrgc/scan_matching/AnchorGrid.h>

#include <mrpt/core/exceptions.h>

#include <algorithm>

namespace lrgc
{
namespace
{
constexpr uint64_t kHashMul = 0x9E3779B97F4A7C15ULL;  // Fibonacci hashing
}

CAnchorGrid::CAnchorGrid(
	const std::vector<Eigen::Vector2d>& points, const std::vector<bool>& usable, double cell)
	: m_cell(cell)
{
	ASSERT_EQUAL_(points.size(), usable.size());
	ASSERT_(cell > 0);
	const size_t n = points.size();
	if (n == 0) return;
	std::vector<uint64_t> keys(n);
	for (size_t i = 0; i < n; ++i)
		keys[i] = cellKey(cellIndex(points[i].x(), m_cell), cellIndex(points[i].y(), m_cell));
	for (uint32_t i = 0; i < n; ++i)
		if (usable[i]) m_index.push_back(i);
	std::sort(m_index.begin(), m_index.end(), [&](uint32_t a, uint32_t b) { return keys[a] < keys[b]; });
	const size_t nUsable = m_index.size();
	m_pos.resize(nUsable);
	for (size_t k = 0; k < nUsable; ++k) m_pos[k] = points[m_index[k]];
	size_t cells = 0;
	for (size_t k = 0; k < nUsable; ++k) cells += (k == 0 || keys[m_index[k]] != keys[m_index[k - 1]]);
	size_t size = 16;
	while (size < 2 * cells) size *= 2;
	m_table.assign(size, TCell{});
	m_mask = size - 1;
	for (size_t k = 0; k < nUsable;)
	{
		const uint64_t key = keys[m_index[k]];
		size_t m = k;
		while (m < nUsable && keys[m_index[m]] == key) ++m;
		uint64_t slot = (key * kHashMul) >> 40 & m_mask;
		while (m_table[slot].count != 0) slot = (slot + 1) & m_mask;
		m_table[slot] = {key, static_cast<uint32_t>(k), static_cast<uint32_t>(m - k)};
		k = m;
	}
}

const CAnchorGrid::TCell* CAnchorGrid::findCell(int64_t ix, int64_t iy) const
{
	const uint64_t key = cellKey(ix, iy);
	for (uint64_t slot = (key * kHashMul) >> 40 & m_mask;; slot = (slot + 1) & m_mask)
	{
		const TCell& c = m_table[slot];
		if (c.count == 0) return nullptr;
		if (c.key == key) return &c;
	}
}

int CAnchorGrid::nearest(const Eigen::Vector2d& q, double maxDist, double* d2Out) const
{
	if (m_table.empty() || !(maxDist > 0)) return -1;
	// Ring search: ring k holds the cells at Chebyshev distance k from q's cell. After ring k,
	// every unvisited point is at least `lb` away (distance from q to the border of the
	// visited block), so the search stops once the best distance is <= lb or lb >= maxDist.
	const int64_t cx = cellIndex(q.x(), m_cell), cy = cellIndex(q.y(), m_cell);
	double best = maxDist * maxDist;
	int bestIdx = -1;
	auto visit = [&](int64_t ix, int64_t iy)
	{
		const TCell* c = findCell(ix, iy);
		if (!c) return;
		for (uint32_t k = c->start; k < c->start + c->count; ++k)
		{
			const double d2 = (m_pos[k] - q).squaredNorm();
			if (d2 < best) best = d2, bestIdx = static_cast<int>(m_index[k]);
		}
	};
	for (int64_t k = 0;; ++k)
	{
		if (k == 0) visit(cx, cy);
		else
		{
			for (int64_t i = -k; i <= k; ++i) visit(cx + i, cy - k), visit(cx + i, cy + k);
			for (int64_t j = -k + 1; j <= k - 1; ++j) visit(cx - k, cy + j), visit(cx + k, cy + j);
		}
		const double lb = std::min(
			std::min(q.x() - (cx - k) * m_cell, (cx + k + 1) * m_cell - q.x()),
			std::min(q.y() - (cy - k) * m_cell, (cy + k + 1) * m_cell - q.y()));
		if (lb * lb >= best) break;
	}
	if (bestIdx >= 0 && d2Out) *d2Out = best;
	return bestIdx;
}

}  // namespace lrgc
