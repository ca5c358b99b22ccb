/* CCorrelationGrid: the "old map" side of the LRGC correlation operator (Gutmann & Konolige,
 * section 2.3), with the max-pooled pyramid used by branch and bound.
 *
 * Map probability p(m_i) of cell i [0,1]: the old map's points are rasterised into cells and
 * the uncertainty is folded into the map as a Gaussian blur of standard deviation sigma [m]:
 *     p(m_i) = max_j exp(-d(i, j)^2 / (2 sigma^2)),  j over occupied cells,
 * i.e. the Gaussian is spread from each occupied cell and overlapping spreads take the max
 * (a "likelihood field", computed with one exact Euclidean distance transform). The max,
 * rather than the sum of a linear blur, makes p(m_i) independent of how densely a wall was
 * sampled and keeps it in [0,1] with 1 on the walls. Values are stored quantised to 0..255
 * (value / 255 is the probability), so correlation sums are exact integers.
 *
 * Pyramid (Cartographer-style sliding-window max, no subsampling): level h holds
 *     P_h(x, y) = max { P_0(x + a, y + b) : 0 <= a, b < 2^h },
 * cells outside the map being 0. A block of 2^h x 2^h translations of a patch can therefore
 * be bounded from above by one lookup per patch point (see PatchCorrelator.h). All levels
 * share one layout, padded on the low side by pad = 2^(numLevels-1) - 1 cells (the cells
 * where a block reaches into the map), so one row-major offset per point serves every level.
 */
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace lrgc
{
class CCorrelationGrid
{
public:
	/** Builds the grid over the bounding box of `pointsInMap` [m] grown by `margin` [m] on
	 * every side, with square cells of `resolution` [m], blurred with `blurSigma` [m], and
	 * `numLevels` pyramid levels (level 0 = the grid itself; 2^(numLevels-1) cells should
	 * span a search window for the fastest search). Throws if points is empty or a
	 * parameter is out of range. */
	static CCorrelationGrid fromPoints(const std::vector<Eigen::Vector2d>& pointsInMap,
									   double resolution, double blurSigma, double margin,
									   int numLevels = 8);

	CCorrelationGrid() = default;

	double resolution() const { return m_resolution; }
	double blurSigma() const { return m_blurSigma; }
	/** Map-frame coordinates [m] of the lower-left corner of cell (0, 0). */
	const Eigen::Vector2d& origin() const { return m_origin; }
	int width() const { return m_width; }
	int height() const { return m_height; }
	int numLevels() const { return static_cast<int>(m_levels.size()); }
	bool empty() const { return m_levels.empty(); }

	/** Cell containing a map-frame point: floor((p - origin) / resolution); may be outside. */
	Eigen::Vector2i cellOf(const Eigen::Vector2d& pInMap) const;

	/** p(m_i) in [0,1] at the cell containing `pInMap`; 0 outside the grid. */
	double probabilityAt(const Eigen::Vector2d& pInMap) const
	{
		const Eigen::Vector2i c = cellOf(pInMap);
		return value(0, c.x(), c.y()) / 255.0;
	}

	/** Quantised value (0..255) of pyramid level `level` at cell (cx, cy); 0 outside. */
	uint8_t value(int level, int cx, int cy) const
	{
		const unsigned ux = static_cast<unsigned>(cx + m_pad);
		const unsigned uy = static_cast<unsigned>(cy + m_pad);
		if (ux >= static_cast<unsigned>(m_stride) || uy >= static_cast<unsigned>(m_rows))
			return 0;
		return m_levels[static_cast<size_t>(level)]
					   [static_cast<size_t>(uy) * static_cast<size_t>(m_stride) + ux];
	}

	/** Raw storage, for tight loops: value(level, cx, cy) is
	 * levelData(level)[(cy + pad) * stride + (cx + pad)] when cx + pad is in [0, stride) and
	 * cy + pad in [0, rows). */
	const uint8_t* levelData(int level) const
	{
		return m_levels[static_cast<size_t>(level)].data();
	}
	int pad() const { return m_pad; }
	int stride() const { return m_stride; }  //!< width + pad
	int rows() const { return m_rows; }      //!< height + pad

private:
	double m_resolution = 0;
	double m_blurSigma = 0;
	Eigen::Vector2d m_origin = Eigen::Vector2d::Zero();
	int m_width = 0, m_height = 0;
	int m_pad = 0, m_stride = 0, m_rows = 0;
	std::vector<std::vector<uint8_t>> m_levels;
};

}  // namespace lrgc
