/* Building the blurred old-map grid and its max-pooled pyramid (see CorrelationGrid.h).
 *
 * Blur: p = exp(-(d * res)^2 / (2 sigma^2)) through a lookup table on the integer squared
 * distance d^2 [cells^2] from a cell to its nearest occupied cell, zero beyond the table.
 * Either the table's disc is stamped (max) around every occupied cell -- cheap for sparse
 * points and a small sigma, the loop-closing case -- or one exact Euclidean distance
 * transform (OpenCV, DIST_MASK_PRECISE) gives d; both yield the same values.
 * Pyramid: level h from level h-1 by doubling, P_h(x) = max(P_{h-1}(x), P_{h-1}(x + s)) with
 * s = 2^(h-1), first along rows then along columns.
 */
#include <lrgc/loop_closing/CorrelationGrid.h>

#include <mrpt/core/exceptions.h>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace lrgc
{
namespace
{
// Largest grid accepted (cells), to turn a wrong unit or a stray far point into an error
// rather than an allocation of gigabytes: 2^28 cells = 16384 x 16384.
constexpr double kMaxCells = 268435456.0;

// Quantised p(d) = round(255 exp(-d^2 res^2 / (2 sigma^2))) for integer squared distances
// d2 [cells^2]; beyond the table the value is 0.
std::vector<uint8_t> blurTable(double resolution, double blurSigma)
{
	if (blurSigma <= 0) return {255};
	const double k = resolution * resolution / (2 * blurSigma * blurSigma);
	// 255 exp(-k d2) < 0.5  <=>  d2 > ln(510) / k
	const size_t n = static_cast<size_t>(std::ceil(std::log(510.0) / k)) + 1;
	std::vector<uint8_t> lut(n);
	for (size_t d2 = 0; d2 < n; ++d2)
		lut[d2] = static_cast<uint8_t>(std::lround(255.0 * std::exp(-k * double(d2))));
	return lut;
}

// Next pyramid level in the common padded layout (rows x stride, row-major): with
// s = 2^(h-1), P_h(x, y) = max over {x, x+s} x {y, y+s} of P_{h-1}, reads past the stored high
// end being zeros (so the max is the value itself there). Rows then columns; plain loops the
// compiler vectorises, without padded copies.
std::vector<uint8_t> nextLevel(const std::vector<uint8_t>& prev, int rows, int stride, int s)
{
	const size_t w = size_t(stride);
	std::vector<uint8_t> next(prev.size());
	for (size_t r = 0; r < size_t(rows); ++r)
	{  // next(r, c) = max(prev(r, c), prev(r, c + s))
		const uint8_t* in = prev.data() + r * w;
		uint8_t* out = next.data() + r * w;
		const size_t n = w > size_t(s) ? w - size_t(s) : 0;
		for (size_t c = 0; c < n; ++c) out[c] = std::max(in[c], in[c + size_t(s)]);
		for (size_t c = n; c < w; ++c) out[c] = in[c];
	}
	for (size_t r = 0; r + size_t(s) < size_t(rows); ++r)
	{  // next(r, c) = max(next(r, c), next(r + s, c)), rows in increasing order
		uint8_t* out = next.data() + r * w;
		const uint8_t* below = out + size_t(s) * w;
		for (size_t c = 0; c < w; ++c) out[c] = std::max(out[c], below[c]);
	}
	return next;
}

// Level 0 from the occupied cells, by stamping the disc of the lookup table around each:
// max_j lut[d2(i, j)] = lut[min_j d2(i, j)] since the table does not increase with d2, so this
// equals the distance-transform result whenever the stamps are cheaper than a whole-grid pass.
void stampLevel0(const std::vector<Eigen::Vector2i>& occupied, const std::vector<uint8_t>& lut,
				 int width, int height, int pad, int stride, uint8_t* L0)
{
	const int R = static_cast<int>(std::floor(std::sqrt(double(lut.size() - 1))));
	for (const auto& o : occupied)
		for (int dy = std::max(-R, -o.y()); dy <= std::min(R, height - 1 - o.y()); ++dy)
		{
			const int rx = static_cast<int>(
				std::floor(std::sqrt(double(lut.size() - 1 - size_t(dy * dy)))));
			const int x0 = std::max(-rx, -o.x()), x1 = std::min(rx, width - 1 - o.x());
			uint8_t* row = L0 + size_t(o.y() + dy + pad) * size_t(stride) + size_t(o.x() + pad);
			for (int dx = x0; dx <= x1; ++dx)
				row[dx] = std::max(row[dx], lut[size_t(dx * dx + dy * dy)]);
		}
}

// Level 0 from the occupied cells by an exact Euclidean distance transform (OpenCV): each
// cell's value is lut[d^2], d the distance to the nearest occupied cell [cells].
void distanceLevel0(const std::vector<Eigen::Vector2i>& occupied,
					const std::vector<uint8_t>& lut, int width, int height, int pad, int stride,
					uint8_t* L0)
{
	// Occupied cells are 0 (distanceTransform measures the distance to the nearest zero).
	cv::Mat free(height, width, CV_8U, cv::Scalar(255));
	for (const auto& c : occupied) free.at<uint8_t>(c.y(), c.x()) = 0;
	cv::Mat dist;
	cv::distanceTransform(free, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
	for (int r = 0; r < height; ++r)
	{
		const float* d = dist.ptr<float>(r);
		uint8_t* out = L0 + static_cast<size_t>(r + pad) * size_t(stride) + size_t(pad);
		for (int c = 0; c < width; ++c)
		{
			// Exact distances are square roots of integers: recover d^2 by rounding.
			const double d2 = std::round(double(d[c]) * double(d[c]));
			out[c] = d2 < double(lut.size()) ? lut[static_cast<size_t>(d2)] : 0;
		}
	}
}
}  // namespace

Eigen::Vector2i CCorrelationGrid::cellOf(const Eigen::Vector2d& pInMap) const
{
	const double fx = std::floor((pInMap.x() - m_origin.x()) / m_resolution);
	const double fy = std::floor((pInMap.y() - m_origin.y()) / m_resolution);
	// Clamp far points to an index that is outside the grid but cannot overflow int.
	const double lim = 1e9;
	return {static_cast<int>(std::clamp(fx, -lim, lim)),
			static_cast<int>(std::clamp(fy, -lim, lim))};
}

CCorrelationGrid CCorrelationGrid::fromPoints(const std::vector<Eigen::Vector2d>& pointsInMap,
											  double resolution, double blurSigma,
											  double margin, int numLevels)
{
	if (pointsInMap.empty())
		THROW_EXCEPTION("CCorrelationGrid::fromPoints: no points to build the old map from");
	if (!(resolution > 0) || !(blurSigma >= 0) || !(margin >= 0) || numLevels < 1 ||
		numLevels > 16)
		THROW_EXCEPTION_FMT(
			"CCorrelationGrid::fromPoints: bad parameters resolution=%g m, blurSigma=%g m, "
			"margin=%g m, numLevels=%d (need resolution > 0, sigma >= 0, margin >= 0, "
			"1 <= levels <= 16)",
			resolution, blurSigma, margin, numLevels);

	Eigen::Vector2d lo = pointsInMap.front(), hi = lo;
	for (const auto& p : pointsInMap)
	{
		if (!p.allFinite())
			THROW_EXCEPTION("CCorrelationGrid::fromPoints: a point is not finite");
		lo = lo.cwiseMin(p);
		hi = hi.cwiseMax(p);
	}
	const double wd = std::ceil((hi.x() - lo.x() + 2 * margin) / resolution) + 1;
	const double hd = std::ceil((hi.y() - lo.y() + 2 * margin) / resolution) + 1;
	if (wd * hd > kMaxCells)
		THROW_EXCEPTION_FMT(
			"CCorrelationGrid::fromPoints: %.0f x %.0f cells at %g m is too large (points "
			"span %.1f x %.1f m)",
			wd, hd, resolution, hi.x() - lo.x(), hi.y() - lo.y());

	CCorrelationGrid g;
	g.m_resolution = resolution;
	g.m_blurSigma = blurSigma;
	g.m_origin = lo - Eigen::Vector2d(margin, margin);
	g.m_width = static_cast<int>(wd);
	g.m_height = static_cast<int>(hd);

	const std::vector<uint8_t> lut = blurTable(resolution, blurSigma);
	g.m_pad = (1 << (numLevels - 1)) - 1;
	g.m_stride = g.m_width + g.m_pad;
	g.m_rows = g.m_height + g.m_pad;
	std::vector<uint8_t> L0(static_cast<size_t>(g.m_stride) * static_cast<size_t>(g.m_rows), 0);

	// Occupied cells, each once.
	std::vector<uint8_t> occ(size_t(g.m_width) * size_t(g.m_height), 0);
	std::vector<Eigen::Vector2i> occupied;
	for (const auto& p : pointsInMap)
	{
		const Eigen::Vector2i c = g.cellOf(p);
		if (c.x() < 0 || c.y() < 0 || c.x() >= g.m_width || c.y() >= g.m_height) continue;
		uint8_t& o = occ[size_t(c.y()) * size_t(g.m_width) + size_t(c.x())];
		if (!o) o = 1, occupied.push_back(c);
	}
	// Stamp cost ~ (occupied cells) x (disc of the table); a distance transform ~ a few passes
	// over the grid. Both give the same values (see stampLevel0).
	const double stampCost = double(occupied.size()) * M_PI * double(lut.size());
	if (stampCost < 4.0 * wd * hd)
		stampLevel0(occupied, lut, g.m_width, g.m_height, g.m_pad, g.m_stride, L0.data());
	else
		distanceLevel0(occupied, lut, g.m_width, g.m_height, g.m_pad, g.m_stride, L0.data());
	g.m_levels.push_back(std::move(L0));
	for (int h = 1; h < numLevels; ++h)
		g.m_levels.push_back(nextLevel(g.m_levels.back(), g.m_rows, g.m_stride, 1 << (h - 1)));
	return g;
}

}  // namespace lrgc
