/* Building the blurred old-map grid and its max-pooled pyramid (see CorrelationGrid.h).
 *
 * Blur: one exact Euclidean distance transform (OpenCV, DIST_MASK_PRECISE) of the occupied
 * cells gives the distance d [cells] from every cell to its nearest occupied cell; then
 * p = exp(-(d * res)^2 / (2 sigma^2)) through a lookup table on the integer d^2.
 * Pyramid: level h from level h-1 by doubling, P_h(x) = max(P_{h-1}(x), P_{h-1}(x + s)) with
 * s = 2^(h-1), first along rows then along columns, on zero-padded OpenCV views (SIMD max).
 */
#include "lrgc/CorrelationGrid.h"

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
// s = 2^(h-1), P_h(x, y) = max over {x, x+s} x {y, y+s} of P_{h-1}; reads past the stored
// high end are zeros of the padded copy Z.
std::vector<uint8_t> nextLevel(const std::vector<uint8_t>& prev, int rows, int stride, int s)
{
	cv::Mat Z = cv::Mat::zeros(rows + s, stride + s, CV_8U);
	const cv::Mat P(rows, stride, CV_8U, const_cast<uint8_t*>(prev.data()));
	P.copyTo(Z(cv::Rect(0, 0, stride, rows)));
	cv::Mat T;  // T(r, c) = max(Z(r, c), Z(r, c + s))
	cv::max(Z(cv::Rect(0, 0, stride, rows + s)), Z(cv::Rect(s, 0, stride, rows + s)), T);
	std::vector<uint8_t> next(prev.size());
	cv::Mat out(rows, stride, CV_8U, next.data());  // out(r, c) = max(T(r, c), T(r + s, c))
	cv::max(T(cv::Rect(0, 0, stride, rows)), T(cv::Rect(0, s, stride, rows)), out);
	return next;
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

	// Occupied cells are 0 (distanceTransform measures the distance to the nearest zero).
	cv::Mat free(g.m_height, g.m_width, CV_8U, cv::Scalar(255));
	for (const auto& p : pointsInMap)
	{
		const Eigen::Vector2i c = g.cellOf(p);
		if (c.x() >= 0 && c.y() >= 0 && c.x() < g.m_width && c.y() < g.m_height)
			free.at<uint8_t>(c.y(), c.x()) = 0;
	}
	cv::Mat dist;
	cv::distanceTransform(free, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);

	const std::vector<uint8_t> lut = blurTable(resolution, blurSigma);
	g.m_pad = (1 << (numLevels - 1)) - 1;
	g.m_stride = g.m_width + g.m_pad;
	g.m_rows = g.m_height + g.m_pad;
	std::vector<uint8_t> L0(static_cast<size_t>(g.m_stride) * static_cast<size_t>(g.m_rows), 0);
	for (int r = 0; r < g.m_height; ++r)
	{
		const float* d = dist.ptr<float>(r);
		uint8_t* out =
			L0.data() + static_cast<size_t>(r + g.m_pad) * size_t(g.m_stride) + size_t(g.m_pad);
		for (int c = 0; c < g.m_width; ++c)
		{
			// Exact distances are square roots of integers: recover d^2 by rounding.
			const double d2 = std::round(double(d[c]) * double(d[c]));
			out[c] = d2 < double(lut.size()) ? lut[static_cast<size_t>(d2)] : 0;
		}
	}
	g.m_levels.push_back(std::move(L0));
	for (int h = 1; h < numLevels; ++h)
		g.m_levels.push_back(nextLevel(g.m_levels.back(), g.m_rows, g.m_stride, 1 << (h - 1)));
	return g;
}

}  // namespace lrgc
