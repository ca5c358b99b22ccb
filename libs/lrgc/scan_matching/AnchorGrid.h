/* CAnchorGrid: exact nearest-neighbour and radius queries over a fixed set of 2D points (the
 * anchors of a CReferenceCloud), for the correspondence search of scan matching.
 *
 * Method: points are bucketed in square cells of side `cell` [m], the occupied cells kept in an
 * open-addressing hash table (Fibonacci hashing, linear probing) pointing at runs of a
 * cell-sorted copy of the points. nearest() searches ring by ring around the query's cell with
 * an exact stopping rule (about 50 ns per query indoors); forEachWithin() visits the cells that
 * overlap the query disc. Frames: whatever frame the points are in. Units: metres.
 */
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <vector>

namespace lrgc
{
class CAnchorGrid
{
public:
	CAnchorGrid() = default;
	/** Indexes points[i] for every i with usable[i] (sizes must match). */
	CAnchorGrid(
		const std::vector<Eigen::Vector2d>& points, const std::vector<bool>& usable, double cell);

	bool empty() const { return m_table.empty(); }

	/** Index of the point nearest to q within maxDist [m] (exact; of equally near points, the
	 * first in cell order), or -1. If found and d2 is given, *d2 is the squared distance. */
	int nearest(const Eigen::Vector2d& q, double maxDist, double* d2 = nullptr) const;

	/** Calls fn(index) for every indexed point within radius [m] of q. */
	template <class F>
	void forEachWithin(const Eigen::Vector2d& q, double radius, F&& fn) const;

	static int64_t cellIndex(double v, double cell)
	{
		return static_cast<int64_t>(std::floor(v / cell));
	}

private:
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
	const TCell* findCell(int64_t ix, int64_t iy) const;

	std::vector<Eigen::Vector2d> m_pos;  // indexed points, sorted by cell
	std::vector<uint32_t> m_index;  // their indices in the input
	std::vector<TCell> m_table;  // size: power of two
	uint64_t m_mask = 0;
	double m_cell = 0.1;  // [m]
};

template <class F>
void CAnchorGrid::forEachWithin(const Eigen::Vector2d& q, double radius, F&& fn) const
{
	if (m_table.empty()) return;
	const double r2 = radius * radius;
	const int64_t x0 = cellIndex(q.x() - radius, m_cell), x1 = cellIndex(q.x() + radius, m_cell);
	const int64_t y0 = cellIndex(q.y() - radius, m_cell), y1 = cellIndex(q.y() + radius, m_cell);
	for (int64_t ix = x0; ix <= x1; ++ix)
		for (int64_t iy = y0; iy <= y1; ++iy)
			if (const TCell* c = findCell(ix, iy))
				for (uint32_t k = c->start; k < c->start + c->count; ++k)
					if ((m_pos[k] - q).squaredNorm() <= r2) fn(m_index[k]);
}

}  // namespace lrgc
