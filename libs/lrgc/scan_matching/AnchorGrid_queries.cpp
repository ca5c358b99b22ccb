/* CAnchorGrid's queries (AnchorGrid.h): a cell's lookup and the nearest-point searches, the
 * ring walk over dense tables, the scan of a short sorted run and the rings over the hashed
 * grid. The grid's build is in AnchorGrid.cpp. */
#include <lrgc/scan_matching/AnchorGrid.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace lrgc
{
const CAnchorGrid::TCell* CAnchorGrid::findCell(int64_t ix, int64_t iy) const
{
	const uint64_t key = cellKey(ix, iy);
	for (uint64_t slot = homeSlot(key);; slot = (slot + 1) & m_mask)
	{
		const TCell& c = m_table[slot];
		if (c.count == 0) return nullptr;
		if (c.key == key) return &c;
	}
}

namespace
{
/** Position of cell (dx, dy) (relative to the query's cell) in the ring walk of
 * CAnchorGrid::nearest: ring k = max(|dx|, |dy|), then (cx + i, cy - k), (cx + i, cy + k) for
 * i = -k..k, then (cx - k, cy + j), (cx + k, cy + j) for j = -k+1..k-1. */
std::pair<int64_t, int64_t> ringRank(int64_t dx, int64_t dy)
{
	const int64_t k = std::max(std::abs(dx), std::abs(dy));
	if (k == 0) return {0, 0};
	if (std::abs(dy) == k) return {k, 2 * (dx + k) + (dy > 0)};
	return {k, 2 * (2 * k + 1) + 2 * (dy + k - 1) + (dx > 0)};
}
/** Whether p comes before b in the ring walk around cell (cx, cy) (cells of side `cell`). */
bool ringBefore(const Eigen::Vector2d& p, const Eigen::Vector2d& b, int64_t cx, int64_t cy,
				double cell)
{
	return ringRank(CAnchorGrid::cellIndex(p.x(), cell) - cx,
					CAnchorGrid::cellIndex(p.y(), cell) - cy) <
		   ringRank(CAnchorGrid::cellIndex(b.x(), cell) - cx,
					CAnchorGrid::cellIndex(b.y(), cell) - cy);
}

/** Reads the points [p, end) for a nearest-point search at q: calls take(k, d2) for each
 * point k (offset from p) at squared distance d2 = (p[k] - q).squaredNorm() [m^2] in order,
 * except for points farther than `best` (which take() may lower) read in a pair with another
 * such point, and returns the least squared distance of those (infinity if none). For a
 * take() that, for a point farther than best, only lowers a running minimum by d2, this is
 * the same as take() on every point: min is exact and the distances are finite. With SSE2
 * two points in one pass: lanes (dx0, dy0), (dx1, dy1), then (dx0^2, dx1^2) + (dy0^2, dy1^2),
 * each sum the same dx dx + dy dy as squaredNorm()'s. */
template <class Take>
double scanPoints(const Eigen::Vector2d* p, const Eigen::Vector2d* end,
				  const Eigen::Vector2d& q, const double& best, Take&& take)
{
	const Eigen::Vector2d* k = p;
#if defined(__SSE2__)
	const __m128d qv = _mm_loadu_pd(q.data());
	__m128d farMin = _mm_set1_pd(std::numeric_limits<double>::infinity());
	for (__m128d bestv = _mm_set1_pd(best); end - k >= 2; k += 2)
	{
		const __m128d a = _mm_sub_pd(_mm_loadu_pd(k[0].data()), qv),
					  b = _mm_sub_pd(_mm_loadu_pd(k[1].data()), qv);
		const __m128d a2 = _mm_mul_pd(a, a), b2 = _mm_mul_pd(b, b);
		const __m128d d = _mm_add_pd(_mm_unpacklo_pd(a2, b2), _mm_unpackhi_pd(a2, b2));
		if (_mm_movemask_pd(_mm_cmple_pd(d, bestv)) == 0)
		{
			farMin = _mm_min_pd(farMin, d);
			continue;
		}
		take(static_cast<uint32_t>(k - p), _mm_cvtsd_f64(d));
		take(static_cast<uint32_t>(k - p) + 1, _mm_cvtsd_f64(_mm_unpackhi_pd(d, d)));
		bestv = _mm_set1_pd(best);
	}
	double lanes[2];
	_mm_storeu_pd(lanes, farMin);
	double far = std::min(lanes[0], lanes[1]);
#else
	double far = std::numeric_limits<double>::infinity();
	for (; end - k >= 2; k += 2)
	{
		const double d0 = (k[0] - q).squaredNorm(), d1 = (k[1] - q).squaredNorm();
		if (d0 > best && d1 > best)
		{
			far = std::min(far, std::min(d0, d1));
			continue;
		}
		take(static_cast<uint32_t>(k - p), d0);
		take(static_cast<uint32_t>(k - p) + 1, d1);
	}
#endif
	if (k < end) take(static_cast<uint32_t>(k - p), (k[0] - q).squaredNorm());
	return far;
}

/** Distance [m] from q to the border of the block of rings 0..k around cell (cx, cy). */
double ringGap(const Eigen::Vector2d& q, int64_t cx, int64_t cy, int64_t k, double cell)
{
	return std::min(std::min(q.x() - (cx - k) * cell, (cx + k + 1) * cell - q.x()),
					std::min(q.y() - (cy - k) * cell, (cy + k + 1) * cell - q.y()));
}

/** False if every point of a ring side whose cells lie at least `gap` [m] from the query
 * (the distance to the side's inner edge) is certainly farther than sqrt(far) [m], far a
 * squared distance [m^2] at least the best one's: no point there can be nearer, tie or
 * lower the second-nearest distance (when far is that distance). The
 * slack covers the rounding of the cell indices and edges (relative ~1e-16 of the
 * coordinates, which CAnchorGrid bounds by kMaxCoordinate). */
bool mayMatter(double gap, double far)
{
	constexpr double kSlack_m = 1e-6;
	const double lb = gap - kSlack_m;
	return !(lb > 0 && lb * lb > far);
}
}  // namespace

/** The nearest point read so far (strictly nearer wins: of equal distances the first read
 * stays) and, with kBound, the least squared distance [m^2] of the other points read. The
 * plain searches' running answer (nearestByScan, nearestRings); nearestDense's TNearest adds
 * the ring walk's tie rule. */
template <bool kBound>
struct CAnchorGrid::TNearestSoFar
{
	double best;  //!< [m^2] maxDist^2 until a point is nearer
	double second = std::numeric_limits<double>::infinity();
	int idx = -1;

	void offer(double d2, uint32_t index)
	{
		if (d2 < best)
		{
			if (kBound && idx >= 0) second = std::min(second, best);
			best = d2, idx = static_cast<int>(index);
		}
		else if (kBound)
			second = std::min(second, d2);
	}
};

/** A run [b, e) of points (pos) and their indices in the input (index). */
struct CAnchorGrid::TRun
{
	const Eigen::Vector2d* pos;
	const uint32_t* index;
	uint32_t b, e;
};

/** The running answer of CAnchorGrid::nearestDense's ring walk around cell (cx, cy) (cells
 * of side `cell` [m]): the best squared distance [m^2] (maxDist^2 until a point is nearer),
 * its point, and with kBound the least squared distance of the other points read. */
template <bool kBound>
struct CAnchorGrid::TNearest
{
	int64_t cx, cy;
	double cell, best, second = std::numeric_limits<double>::infinity();
	int idx = -1;
	Eigen::Vector2d pos = Eigen::Vector2d::Zero();

	/** Point k of run r at squared distance d2, in the walk's order: of equally near points
	 * in different cells the one the ring walk visits first is kept (ringRank), in one cell
	 * the first of its run. */
	void take(const TRun& r, uint32_t k, double d2)
	{
		if (d2 < best)
		{
			if (kBound && idx >= 0) second = std::min(second, best);
			best = d2, idx = static_cast<int>(r.index[k]), pos = r.pos[k];
			return;
		}
		if (kBound) second = std::min(second, d2);
		if (d2 == best && idx >= 0 && ringBefore(r.pos[k], pos, cx, cy, cell))
			idx = static_cast<int>(r.index[k]), pos = r.pos[k];
	}
};

template <bool kBound>
int CAnchorGrid::nearestDense(const Eigen::Vector2d& q, double maxDist, double* d2Out,
							  double* boundOut) const
{
	if (m_rowStart.empty())
		return nearestByScan<kBound>(q, maxDist, d2Out, boundOut);  // a radiusOnly grid
	// The ring walk of nearest() with each ring read as four runs: its bottom and top rows
	// from the row-major table, its left and right columns (corners excluded) from the
	// column-major one. A ring holds the same points whatever the order, so the best
	// distance after each ring, hence the stopping ring, are the ring walk's; ties are
	// resolved as there (TNearest::take).
	const int64_t cx = cellIndex(q.x(), m_cell), cy = cellIndex(q.y(), m_cell);
	TNearest<kBound> n{cx, cy, m_cell, maxDist * maxDist};
	// Cells (ix, y0..y1) of the column table, (x0..x1, iy) of the row table, clipped to the
	// box (an empty run if none, still pointing into its table: no pointer arithmetic starts
	// from null).
	auto column = [&](int64_t ix, int64_t y0, int64_t y1)
	{
		const int64_t dx = ix - m_x0, dy0 = std::max<int64_t>(y0 - m_y0, 0),
					  dy1 = std::min(y1 - m_y0, m_ny - 1);
		if (dx < 0 || dx >= m_nx || dy0 > dy1) return TRun{m_pos.data(), m_index.data(), 0, 0};
		return TRun{m_pos.data(), m_index.data(), m_start[dx * m_ny + dy0],
					m_start[dx * m_ny + dy1 + 1]};
	};
	auto row = [&](int64_t iy, int64_t x0, int64_t x1)
	{
		const int64_t dy = iy - m_y0, dx0 = std::max<int64_t>(x0 - m_x0, 0),
					  dx1 = std::min(x1 - m_x0, m_nx - 1);
		if (dy < 0 || dy >= m_ny || dx0 > dx1)
			return TRun{m_rowPos.data(), m_rowIndex.data(), 0, 0};
		return TRun{m_rowPos.data(), m_rowIndex.data(), m_rowStart[dy * m_nx + dx0],
					m_rowStart[dy * m_nx + dx1 + 1]};
	};
	const int64_t last = lastRing(cx, cy);
	double unread = std::numeric_limits<double>::infinity();  // distance to unread cells [m]
	for (int64_t k = 0; k <= last; ++k)
	{
		// The ring's runs, then their points read in one loop (one copy of it, inlined). A
		// side whose points all lie farther than the second-nearest distance read before the
		// ring (kBound; else the nearest) cannot change the nearest, its ties or `second`:
		// skipped.
		TRun runs[4];
		int nRuns = 0;
		const double far = kBound ? n.second : n.best;
		if (k == 0) runs[nRuns++] = column(cx, cy, cy);
		if (k > 0 && mayMatter(q.y() - (cy - k + 1) * m_cell, far))
			runs[nRuns++] = row(cy - k, cx - k, cx + k);
		if (k > 0 && mayMatter((cy + k) * m_cell - q.y(), far))
			runs[nRuns++] = row(cy + k, cx - k, cx + k);
		if (k > 0 && mayMatter(q.x() - (cx - k + 1) * m_cell, far))
			runs[nRuns++] = column(cx - k, cy - k + 1, cy + k - 1);
		if (k > 0 && mayMatter((cx + k) * m_cell - q.x(), far))
			runs[nRuns++] = column(cx + k, cy - k + 1, cy + k - 1);
		for (int i = 0; i < nRuns; ++i)
		{
			const TRun& r = runs[i];
			const double rest =
				scanPoints(r.pos + r.b, r.pos + r.e, q, n.best,
						   [&](uint32_t m, double d2) { n.take(r, r.b + m, d2); });
			if (kBound) n.second = std::min(n.second, rest);
		}
		const double lb = ringGap(q, cx, cy, k, m_cell);
		if (lb * lb >= n.best)
		{
			unread = lb;
			break;
		}
	}
	if (kBound) *boundOut = std::min(std::sqrt(n.second), unread);
	if (n.idx >= 0 && d2Out) *d2Out = n.best;
	return n.idx;
}

template <bool kBound>
int CAnchorGrid::nearestByScan(const Eigen::Vector2d& q, double maxDist, double* d2Out,
							   double* boundOut) const
{
	TNearestSoFar<kBound> n{maxDist * maxDist};
	for (size_t k = 0; k < m_pos.size(); ++k) n.offer((m_pos[k] - q).squaredNorm(), m_index[k]);
	if (kBound) *boundOut = std::sqrt(n.second);  // every point read
	if (n.idx >= 0 && d2Out) *d2Out = n.best;
	return n.idx;
}

template <bool kBound>
int CAnchorGrid::nearestImpl(const Eigen::Vector2d& q, double maxDist, double* d2Out,
							 double* boundOut) const
{
	if (m_pos.empty() || !(maxDist > 0) || !mayHaveWithin(q, maxDist))
	{
		// No point, or none within maxDist (q is farther than that from their cells' box).
		if (kBound)
			*boundOut = m_pos.empty()                  ? std::numeric_limits<double>::infinity()
						: q.allFinite() && maxDist > 0 ? maxDist
													   : 0.0;
		return -1;
	}
	const int64_t qx = cellIndex(q.x(), m_cell), qy = cellIndex(q.y(), m_cell);
	if (std::min(double(lastRing(qx, qy)), maxDist / m_cell + 1) > double(kMaxRings))
		return nearestByScan<kBound>(q, maxDist, d2Out, boundOut);
	if (isDense()) return nearestDense<kBound>(q, maxDist, d2Out, boundOut);
	return nearestRings<kBound>(q, maxDist, d2Out, boundOut);
}

template <bool kBound>
int CAnchorGrid::nearestRings(const Eigen::Vector2d& q, double maxDist, double* d2Out,
							  double* boundOut) const
{
	// Ring search: ring k holds the cells at Chebyshev distance k from q's cell. After ring k,
	// every unvisited point is at least `lb` away (distance from q to the border of the
	// visited block), so the search stops once the best distance is <= lb or lb >= maxDist.
	const int64_t cx = cellIndex(q.x(), m_cell), cy = cellIndex(q.y(), m_cell);
	TNearestSoFar<kBound> n{maxDist * maxDist};
	auto visit = [&](int64_t ix, int64_t iy)
	{
		const auto [b, e] = cellRun(ix, iy);
		for (uint32_t k = b; k < e; ++k) n.offer((m_pos[k] - q).squaredNorm(), m_index[k]);
	};
	// Bounded twice: by maxDist (the stopping rule) and by the box (after ring `last`, every
	// occupied cell has been visited), whatever maxDist.
	const int64_t last = lastRing(cx, cy);
	double unread = std::numeric_limits<double>::infinity();  // distance to unread cells [m]
	for (int64_t k = 0; k <= last; ++k)
	{
		if (k == 0)
			visit(cx, cy);
		else
		{
			for (int64_t i = -k; i <= k; ++i) visit(cx + i, cy - k), visit(cx + i, cy + k);
			for (int64_t j = -k + 1; j <= k - 1; ++j)
				visit(cx - k, cy + j), visit(cx + k, cy + j);
		}
		const double lb = ringGap(q, cx, cy, k, m_cell);
		if (lb * lb >= n.best)
		{
			unread = lb;
			break;
		}
	}
	if (kBound) *boundOut = std::min(std::sqrt(n.second), unread);
	if (n.idx >= 0 && d2Out) *d2Out = n.best;
	return n.idx;
}

template int CAnchorGrid::nearestImpl<false>(const Eigen::Vector2d&, double, double*,
											 double*) const;
template int CAnchorGrid::nearestImpl<true>(const Eigen::Vector2d&, double, double*,
											double*) const;

}  // namespace lrgc
