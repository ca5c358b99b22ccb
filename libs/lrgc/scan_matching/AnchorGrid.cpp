/* CAnchorGrid's build (AnchorGrid.h): the points sorted by cell, then the dense table (row or
 * column major) where it is small enough, else the hash table with its column directory and
 * the occupancy bitmap. The queries are in AnchorGrid_queries.cpp. */
#include <lrgc/scan_matching/AnchorGrid.h>

#include <mrpt/core/exceptions.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

namespace lrgc
{
CAnchorGrid::CAnchorGrid(const std::vector<Eigen::Vector2d>& points,
						 const std::vector<bool>& usable, double cell, bool radiusOnly)
	: m_cell(cell)
{
	ASSERT_EQUAL_(points.size(), usable.size());
	ASSERT_(cell > 0);
	const size_t n = points.size();
	if (n == 0) return;
	std::vector<uint64_t> keys(n);
	for (size_t i = 0; i < n; ++i)
		keys[i] = cellKey(cellIndex(points[i].x(), m_cell), cellIndex(points[i].y(), m_cell));
	const auto indexable = [](const Eigen::Vector2d& p)
	{
		return p.allFinite() && std::abs(p.x()) <= kMaxCoordinate &&
			   std::abs(p.y()) <= kMaxCoordinate;
	};
	for (uint32_t i = 0; i < n; ++i)
		if (usable[i] && indexable(points[i])) m_index.push_back(i);
	std::sort(m_index.begin(), m_index.end(),
			  [&](uint32_t a, uint32_t b) { return keys[a] < keys[b]; });
	const size_t nUsable = m_index.size();
	m_pos.resize(nUsable);
	for (size_t k = 0; k < nUsable; ++k) m_pos[k] = points[m_index[k]];
	if (nUsable == 0) return;
	m_bx0 = m_by0 = INT64_MAX, m_bx1 = m_by1 = INT64_MIN;
	for (const uint32_t i : m_index)
	{
		const int64_t ix = cellIndex(points[i].x(), m_cell),
					  iy = cellIndex(points[i].y(), m_cell);
		m_bx0 = std::min(m_bx0, ix), m_bx1 = std::max(m_bx1, ix);
		m_by0 = std::min(m_by0, iy), m_by1 = std::max(m_by1, iy);
	}
	if (buildDense(points, !radiusOnly)) return;
	size_t cells = 0;
	for (size_t k = 0; k < nUsable; ++k)
		cells += (k == 0 || keys[m_index[k]] != keys[m_index[k - 1]]);
	size_t size = 16;
	while (size < 2 * cells) size *= 2;
	m_table.assign(size, TCell{});
	m_mask = size - 1;
	for (size_t k = 0; k < nUsable;)
	{
		const uint64_t key = keys[m_index[k]];
		size_t m = k;
		while (m < nUsable && keys[m_index[m]] == key) ++m;
		uint64_t slot = homeSlot(key);
		while (m_table[slot].count != 0) slot = (slot + 1) & m_mask;
		m_table[slot] = {key, static_cast<uint32_t>(k), static_cast<uint32_t>(m - k)};
		k = m;
	}
	buildBitmap(points);
	buildColumns(points);
}

void CAnchorGrid::buildColumns(const std::vector<Eigen::Vector2d>& points)
{
	// For a box as wide (in cells) as the dense table may be large: 4 bytes a column.
	const double columns = double(m_bx1 - m_bx0) + 1;
	if (columns > double(std::max(kDenseMinCells, kDenseCellsPerPoint * m_index.size())))
		return;
	// The occupied cells in m_pos's (key) order, each with its run, bucketed by column
	// (counting sort) and sorted by iy within it (the key order puts iy < 0 after iy >= 0).
	std::vector<std::pair<size_t, TColumnCell>> cells;
	const auto cellOf = [&](uint32_t k)
	{
		const Eigen::Vector2d& p = points[m_index[k]];
		return std::pair{cellIndex(p.x(), m_cell), cellIndex(p.y(), m_cell)};
	};
	for (uint32_t k = 0; k < m_index.size();)
	{
		const auto [ix, iy] = cellOf(k);
		uint32_t m = k + 1;
		while (m < m_index.size() && cellOf(m) == std::pair{ix, iy}) ++m;
		cells.push_back({static_cast<size_t>(ix - m_bx0), TColumnCell{iy, k, m}});
		k = m;
	}
	const size_t nCols = static_cast<size_t>(columns);
	m_colFirst.assign(nCols + 1, 0);
	for (const auto& c : cells) ++m_colFirst[c.first + 1];
	for (size_t i = 0; i < nCols; ++i) m_colFirst[i + 1] += m_colFirst[i];
	std::vector<uint32_t> next(m_colFirst.begin(), m_colFirst.end() - 1);
	m_colCells.resize(cells.size());
	for (const auto& c : cells) m_colCells[next[c.first]++] = c.second;
	for (size_t i = 0; i < nCols; ++i)
		std::sort(m_colCells.begin() + m_colFirst[i], m_colCells.begin() + m_colFirst[i + 1],
				  [](const TColumnCell& a, const TColumnCell& b) { return a.iy < b.iy; });
}

void CAnchorGrid::buildBitmap(const std::vector<Eigen::Vector2d>& points)
{
	int64_t x0 = INT64_MAX, y0 = INT64_MAX, x1 = INT64_MIN, y1 = INT64_MIN;
	for (const uint32_t i : m_index)
	{
		const int64_t ix = cellIndex(points[i].x(), m_cell),
					  iy = cellIndex(points[i].y(), m_cell);
		x0 = std::min(x0, ix), x1 = std::max(x1, ix), y0 = std::min(y0, iy),
		y1 = std::max(y1, iy);
	}
	const double cells = (double(x1 - x0) + 1) * (double(y1 - y0) + 1);
	if (cells > double(kBitmapMaxCells)) return;
	m_x0 = x0, m_y0 = y0, m_nx = x1 - x0 + 1, m_ny = y1 - y0 + 1;
	m_occupied.assign((static_cast<size_t>(m_nx * m_ny) + 63) / 64, 0);
	for (const uint32_t i : m_index)
	{
		const uint64_t b =
			static_cast<uint64_t>((cellIndex(points[i].x(), m_cell) - m_x0) * m_ny +
								  (cellIndex(points[i].y(), m_cell) - m_y0));
		m_occupied[b >> 6] |= uint64_t(1) << (b & 63);
	}
}

bool CAnchorGrid::buildDense(const std::vector<Eigen::Vector2d>& points, bool rowMajor)
{
	const size_t n = m_index.size();
	std::vector<int64_t> ixs(n), iys(n);
	for (size_t k = 0; k < n; ++k)
		ixs[k] = cellIndex(points[m_index[k]].x(), m_cell),
		iys[k] = cellIndex(points[m_index[k]].y(), m_cell);
	const auto [xMin, xMax] = std::minmax_element(ixs.begin(), ixs.end());
	const auto [yMin, yMax] = std::minmax_element(iys.begin(), iys.end());
	const double cells = (double(*xMax - *xMin) + 1) * (double(*yMax - *yMin) + 1);
	if (cells > double(std::max(kDenseMinCells, kDenseCellsPerPoint * n))) return false;
	m_x0 = *xMin, m_y0 = *yMin, m_nx = *xMax - *xMin + 1, m_ny = *yMax - *yMin + 1;
	const size_t nCells = static_cast<size_t>(m_nx * m_ny);
	// Counting sort by dense cell, stable: each cell keeps the order of the key sort.
	std::vector<uint32_t> cellOf(n);
	m_start.assign(nCells + 1, 0);
	for (size_t k = 0; k < n; ++k)
	{
		cellOf[k] = static_cast<uint32_t>((ixs[k] - m_x0) * m_ny + (iys[k] - m_y0));
		++m_start[cellOf[k] + 1];
	}
	for (size_t c = 0; c < nCells; ++c) m_start[c + 1] += m_start[c];
	std::vector<uint32_t> next(m_start.begin(), m_start.end() - 1), index(n);
	for (size_t k = 0; k < n; ++k)
	{
		const uint32_t to = next[cellOf[k]]++;
		index[to] = m_index[k];
		m_pos[to] = points[m_index[k]];
	}
	const std::vector<uint32_t> byKey = std::exchange(m_index, std::move(index));
	if (!rowMajor) return true;
	// The same, row by row (cells by iy, then ix), for nearest()'s ring rows.
	m_rowStart.assign(nCells + 1, 0);
	for (size_t k = 0; k < n; ++k)
	{
		cellOf[k] = static_cast<uint32_t>((iys[k] - m_y0) * m_nx + (ixs[k] - m_x0));
		++m_rowStart[cellOf[k] + 1];
	}
	for (size_t c = 0; c < nCells; ++c) m_rowStart[c + 1] += m_rowStart[c];
	next.assign(m_rowStart.begin(), m_rowStart.end() - 1);
	m_rowIndex.resize(n);
	m_rowPos.resize(n);
	for (size_t k = 0; k < n; ++k)
	{
		const uint32_t to = next[cellOf[k]]++;
		m_rowIndex[to] = byKey[k];
		m_rowPos[to] = points[byKey[k]];
	}
	return true;
}

}  // namespace lrgc
