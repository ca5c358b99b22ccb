/* CAnchorGrid: exact nearest-neighbour and radius queries over a fixed set of 2D points (the
 * anchors of a CReferenceCloud), for the correspondence search of scan matching.
 *
 * Method: points are bucketed in square cells of side `cell` [m], kept in a cell-sorted copy of
 * the points. A cell's run is found through a dense table over the points' bounding box
 * (prefix offsets, one array read) unless that box holds more than kDenseCellsPerPoint cells
 * per point (far stray returns): then through an open-addressing hash table of the occupied
 * cells (Fibonacci hashing, linear probing), with a bitmap of the occupied cells over the box
 * (1 bit per cell) so that the many empty cells a search visits cost a bit test, not a hash
 * probe, and for the radius queries a directory of the occupied cells column by column (a
 * column's cells y0..y1 found by one binary search and read as one run, or two where the key
 * order wraps at iy = 0). Both modes give the same points in the same order.
 * nearest() searches ring by ring around the query's cell with an exact stopping rule;
 * forEachWithin() visits the cells that overlap the query disc column by column (ix, then iy),
 * a column being one run of the dense table. Frames: whatever frame the points are in.
 * Units: metres.
 */
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace lrgc
{
class CAnchorGrid
{
public:
	CAnchorGrid() = default;
	/** Indexes points[i] for every i with usable[i] (sizes must match). radiusOnly: a grid
	 * for forEachWithin alone leaves out the row-major copy that makes nearest() fast in the
	 * dense mode (nearest() then answers by reading every point). */
	CAnchorGrid(const std::vector<Eigen::Vector2d>& points, const std::vector<bool>& usable,
				double cell, bool radiusOnly = false);

	bool empty() const { return m_pos.empty(); }

	/** Index of the point nearest to q within maxDist [m] (exact; of equally near points, the
	 * first in cell order), or -1. If found and d2 is given, *d2 is the squared distance. */
	int nearest(const Eigen::Vector2d& q, double maxDist, double* d2 = nullptr) const
	{
		return nearestImpl<false>(q, maxDist, d2, nullptr);
	}
	/** nearest() (the same answer) that also bounds the others: every indexed point but the
	 * one returned is at least *otherBound [m] from q; with none returned, every point is. The
	 * bound is the nearest of the other points the search read, or the distance from q to the
	 * cells it left unread, whichever is less (0 for a q that is not finite). So for a query
	 * moved to q', the answer stays the same point j while |q' - p_j| < otherBound - |q' - q|
	 * (triangle inequality; within maxDist' iff |q' - p_j| < maxDist'), and stays none while
	 * otherBound - |q' - q| >= maxDist'. */
	int nearestWithBound(const Eigen::Vector2d& q, double maxDist, double* otherBound) const
	{
		return nearestImpl<true>(q, maxDist, nullptr, otherBound);
	}

	/** Calls fn(index) for every indexed point within radius [m] of q. */
	template <class F>
	void forEachWithin(const Eigen::Vector2d& q, double radius, F&& fn) const
	{
		forEachPointWithin(q, radius, [&](uint32_t i, const Eigen::Vector2d&) { fn(i); });
	}
	/** forEachWithin calling fn(index, point) (the point as indexed: read from the grid's
	 * cell-ordered copy, not from the caller's array). */
	template <class F>
	void forEachPointWithin(const Eigen::Vector2d& q, double radius, F&& fn) const;

	/** Calls visit(b, e) for each run [b, e) of cellPoints() / cellIndices() a radius query
	 * reads, in forEachPointWithin's order: the points within radius of q are those of the
	 * runs with (p - q).squaredNorm() <= radius^2. For loops that keep their sums in
	 * registers (local scalars), which a per-point callback summing into a struct does not
	 * get (the struct stays on the stack: a store and a load on each sum's chain per point). */
	template <class F>
	void forEachRun(const Eigen::Vector2d& q, double radius, F&& visit) const;
	/** The indexed points in cell order, and their indices in the input. */
	const std::vector<Eigen::Vector2d>& cellPoints() const { return m_pos; }
	const std::vector<uint32_t>& cellIndices() const { return m_index; }

	/** floor(v / cell), inline (std::floor is a library call on baseline x86-64), clamped to
	 * +-kMaxCellIndex (NaN: -kMaxCellIndex) so that the cast and the index arithmetic of the
	 * searches cannot overflow, whatever v. */
	static int64_t cellIndex(double v, double cell)
	{
		double q = v / cell;
		if (!(q >= -kMaxCellIndex))
			q = -kMaxCellIndex;
		else if (q > kMaxCellIndex)
			q = kMaxCellIndex;
		const auto t = static_cast<int64_t>(q);  // truncation towards zero
		return t - (static_cast<double>(t) > q);
	}
	/** |cell index| bound: 2^40 cells (5.5e10 m at 5 cm), far beyond any indexed point. */
	static constexpr double kMaxCellIndex = 1099511627776.0;
	/** Points with a coordinate beyond this [m] (or not finite) are not indexed: no map is
	 * 10 000 km wide, and the grid's box (in cells) then stays far from int64's range. */
	static constexpr double kMaxCoordinate = 1e7;

	/** Dense table used for these points (else the hash table); for tests. */
	bool isDense() const { return !m_start.empty(); }
	/** The dense table may hold up to this many cells per indexed point (and at least
	 * kDenseMinCells): 4 bytes each. */
	static constexpr size_t kDenseCellsPerPoint = 64, kDenseMinCells = 1 << 14;
	/** Hashed mode: no bitmap for a box of more cells than this (2 MB of bits). */
	static constexpr size_t kBitmapMaxCells = size_t(1) << 24;

private:
	/** The run [first, second) of m_pos / m_index in cell (ix, iy); empty if none. */
	std::pair<uint32_t, uint32_t> cellRun(int64_t ix, int64_t iy) const
	{
		if (!m_start.empty())
		{
			const int64_t dx = ix - m_x0, dy = iy - m_y0;
			if (dx < 0 || dy < 0 || dx >= m_nx || dy >= m_ny) return {0, 0};
			const size_t i = static_cast<size_t>(dx * m_ny + dy);
			return {m_start[i], m_start[i + 1]};
		}
		if (!maybeOccupied(ix, iy)) return {0, 0};
		if (const TCell* c = findCell(ix, iy)) return {c->start, c->start + c->count};
		return {0, 0};
	}
	/** False only for a cell known to be empty (hashed mode: its bit in m_occupied). */
	bool maybeOccupied(int64_t ix, int64_t iy) const
	{
		if (m_occupied.empty()) return true;
		const int64_t dx = ix - m_x0, dy = iy - m_y0;
		if (dx < 0 || dy < 0 || dx >= m_nx || dy >= m_ny) return false;
		const uint64_t i = static_cast<uint64_t>(dx * m_ny + dy);
		return (m_occupied[i >> 6] >> (i & 63)) & 1;
	}
	/** Hashed mode: the occupied cells' bitmap over the box (none if the box is too large). */
	void buildBitmap(const std::vector<Eigen::Vector2d>& points);
	/** Hashed mode: the column directory (none if the box is too wide). */
	void buildColumns(const std::vector<Eigen::Vector2d>& points);
	/** Hashed mode with the column directory: forEachRun's cells (ix, y0..y1) of a column ix
	 * of the box, in iy order, as runs (cells that follow each other in m_pos as one). */
	template <class F>
	void visitColumn(int64_t ix, int64_t y0, int64_t y1, F&& visit) const;

	// A hash slot: an occupied cell -> the run [start, start + count) of m_pos / m_index.
	struct TCell
	{
		uint64_t key = 0;
		uint32_t start = 0, count = 0;  // count == 0: empty slot
	};
	static uint64_t cellKey(int64_t ix, int64_t iy)
	{
		return (static_cast<uint64_t>(static_cast<uint32_t>(ix)) << 32) |
			   static_cast<uint32_t>(iy);
	}
	/** The slot a key's probe starts at (Fibonacci hashing; linear probing from there). */
	uint64_t homeSlot(uint64_t key) const
	{
		return (key * 0x9E3779B97F4A7C15ULL) >> 40 & m_mask;
	}
	const TCell* findCell(int64_t ix, int64_t iy) const;
	/** nearest() and nearestWithBound(): with kBound, *boundOut gets the bound (the searches
	 * then also keep the second-nearest distance they read). */
	template <bool kBound>
	int nearestImpl(const Eigen::Vector2d& q, double maxDist, double* d2Out,
					double* boundOut) const;
	template <bool kBound>
	int nearestRings(const Eigen::Vector2d& q, double maxDist, double* d2Out,
					 double* boundOut) const;
	template <bool kBound>
	int nearestDense(const Eigen::Vector2d& q, double maxDist, double* d2Out,
					 double* boundOut) const;
	struct TRun;  // nearestDense's runs of points (AnchorGrid_queries.cpp)
	template <bool kBound>
	struct TNearest;  // nearestDense's running answer (AnchorGrid_queries.cpp)
	template <bool kBound>
	struct TNearestSoFar;  // the plain searches' running answer (AnchorGrid_queries.cpp)
	/** Fills the dense table from the key-sorted m_index; false if the box is too large. */
	bool buildDense(const std::vector<Eigen::Vector2d>& points, bool rowMajor);

	/** False if no indexed point can be within maxDist of q (q not finite, or farther than
	 * maxDist from the box of the indexed points' cells): the searches' early exit. */
	bool mayHaveWithin(const Eigen::Vector2d& q, double maxDist) const
	{
		return q.allFinite() && q.x() >= m_bx0 * m_cell - maxDist &&
			   q.x() <= (m_bx1 + 1) * m_cell + maxDist && q.y() >= m_by0 * m_cell - maxDist &&
			   q.y() <= (m_by1 + 1) * m_cell + maxDist;
	}
	/** Searches of more rings, or radius queries over more cells, than this (an absurd maxDist
	 * or radius, far beyond any gate) read every point instead: bounded work whatever the
	 * query. Gates of metres on cells of centimetres never come near. */
	static constexpr int64_t kMaxRings = 4096;
	static constexpr double kMaxVisitedCells = double(size_t(1) << 24);
	/** nearest() by reading every point (the first of equally near ones in m_pos order). */
	template <bool kBound>
	int nearestByScan(const Eigen::Vector2d& q, double maxDist, double* d2Out,
					  double* boundOut) const;
	/** Rings around cell (cx, cy) after which every cell of the box has been visited. */
	int64_t lastRing(int64_t cx, int64_t cy) const
	{
		return std::max(std::max(cx - m_bx0, m_bx1 - cx), std::max(cy - m_by0, m_by1 - cy));
	}

	std::vector<Eigen::Vector2d> m_pos;  // indexed points, sorted by cell
	std::vector<uint32_t> m_index;       // their indices in the input
	std::vector<TCell> m_table;          // size: power of two
	uint64_t m_mask = 0;
	// The box of the indexed points' cells: (m_x0, m_y0) + [0, m_nx) x [0, m_ny).
	// Hashed mode: bit i m_ny + j of m_occupied is set if cell (m_x0 + i, m_y0 + j) holds a
	// point.
	std::vector<uint64_t> m_occupied;
	// Hashed mode's column directory: column m_bx0 + i holds the occupied cells
	// [m_colFirst[i], m_colFirst[i + 1]) of m_colCells, by iy, each with its run [b, e) of
	// m_pos.
	struct TColumnCell
	{
		int64_t iy;
		uint32_t b, e;
	};
	std::vector<uint32_t> m_colFirst;
	std::vector<TColumnCell> m_colCells;
	// Dense table: cell (m_x0 + i, m_y0 + j) holds the run [m_start[i m_ny + j], m_start[.. +
	// 1])
	std::vector<uint32_t> m_start;
	int64_t m_x0 = 0, m_y0 = 0, m_nx = 0, m_ny = 0;
	// The points again in row-major cell order: cell (m_x0 + i, m_y0 + j) holds
	// [m_rowStart[j m_nx + i], m_rowStart[.. + 1]) of m_rowPos / m_rowIndex.
	std::vector<uint32_t> m_rowStart, m_rowIndex;
	std::vector<Eigen::Vector2d> m_rowPos;
	double m_cell = 0.1;  // [m]
	// The box of the indexed points' cells in every mode: [m_bx0, m_bx1] x [m_by0, m_by1].
	int64_t m_bx0 = 0, m_bx1 = -1, m_by0 = 0, m_by1 = -1;
};

template <class F>
void CAnchorGrid::forEachPointWithin(const Eigen::Vector2d& q, double radius, F&& fn) const
{
	const double r2 = radius * radius;
	forEachRun(q, radius,
			   [&](uint32_t b, uint32_t e)
			   {
				   for (uint32_t k = b; k < e; ++k)
					   if ((m_pos[k] - q).squaredNorm() <= r2) fn(m_index[k], m_pos[k]);
			   });
}

template <class F>
void CAnchorGrid::forEachRun(const Eigen::Vector2d& q, double radius, F&& visit) const
{
	if (m_pos.empty() || !mayHaveWithin(q, radius)) return;
	// The disc's cells, clipped to the box (cells outside it are empty).
	const int64_t x0 = std::max(cellIndex(q.x() - radius, m_cell), m_bx0),
				  x1 = std::min(cellIndex(q.x() + radius, m_cell), m_bx1);
	const int64_t y0 = std::max(cellIndex(q.y() - radius, m_cell), m_by0),
				  y1 = std::min(cellIndex(q.y() + radius, m_cell), m_by1);
	if ((double(x1) - double(x0) + 1) * (double(y1) - double(y0) + 1) > kMaxVisitedCells)
	{
		visit(0, static_cast<uint32_t>(m_pos.size()));  // an absurd radius: read them all
		return;
	}
	if (!m_start.empty())
	{
		// Dense table: the cells y0..y1 of a column are one run of m_pos, in (iy, run) order.
		const int64_t dy0 = std::max<int64_t>(y0 - m_y0, 0),
					  dy1 = std::min(y1 - m_y0, m_ny - 1);
		if (dy0 > dy1) return;
		for (int64_t dx = std::max<int64_t>(x0 - m_x0, 0); dx <= std::min(x1 - m_x0, m_nx - 1);
			 ++dx)
			visit(m_start[dx * m_ny + dy0], m_start[dx * m_ny + dy1 + 1]);
		return;
	}
	if (!m_colFirst.empty())
	{
		for (int64_t ix = x0; ix <= x1; ++ix) visitColumn(ix, y0, y1, visit);
		return;
	}
	for (int64_t ix = x0; ix <= x1; ++ix)
		for (int64_t iy = y0; iy <= y1; ++iy)
			if (maybeOccupied(ix, iy))
				if (const TCell* c = findCell(ix, iy)) visit(c->start, c->start + c->count);
}

template <class F>
void CAnchorGrid::visitColumn(int64_t ix, int64_t y0, int64_t y1, F&& visit) const
{
	const size_t col = static_cast<size_t>(ix - m_bx0);
	const TColumnCell* c = m_colCells.data() + m_colFirst[col];
	const TColumnCell* const end = m_colCells.data() + m_colFirst[col + 1];
	c = std::lower_bound(c, end, y0,
						 [](const TColumnCell& cell, int64_t y) { return cell.iy < y; });
	if (c == end || c->iy > y1) return;
	// The cells' runs in iy order, those that follow each other in m_pos as one: the same
	// points in the same order as cell by cell.
	uint32_t b = c->b, e = c->e;
	for (++c; c != end && c->iy <= y1; ++c)
	{
		if (c->b != e)
		{
			visit(b, e);
			b = c->b;
		}
		e = c->e;
	}
	visit(b, e);
}

}  // namespace lrgc
