#include <lrgc/scan_matching/RangeDenoiser.h>

#include <algorithm>
#include <cmath>

namespace lrgc
{
namespace
{
constexpr double kMaxSurfaceStep_m = 1.0;

bool returned(const mrpt::obs::CObservation2DRangeScan& obs, size_t i)
{
	const double r = obs.getScanRange(i);
	return obs.getScanRangeValidity(i) && std::isfinite(r) && r > 0 && r < obs.maxRange;
}

/** Prefix sums of x, y, xx, xy, yy over the valid returns (sensor frame), for O(1) window
 * line fits. */
struct TPrefixSums
{
	std::vector<double> x{0}, y{0}, xx{0}, xy{0}, yy{0};
	void add(double px, double py)
	{
		x.push_back(x.back() + px), y.push_back(y.back() + py);
		xx.push_back(xx.back() + px * px), xy.push_back(xy.back() + px * py);
		yy.push_back(yy.back() + py * py);
	}
};

/** Total-least-squares line through returns [a, b) of the valid list: centroid (cx, cy),
 * unit normal (nx, ny), mean squared perpendicular residual (the covariance's smaller
 * eigenvalue). */
struct TLineFit
{
	double cx = 0, cy = 0, nx = 0, ny = 0, residual = 0;
};

TLineFit fitLine(const TPrefixSums& s, size_t a, size_t b)
{
	const double n = double(b - a);
	TLineFit f;
	f.cx = (s.x[b] - s.x[a]) / n, f.cy = (s.y[b] - s.y[a]) / n;
	const double sxx = (s.xx[b] - s.xx[a]) / n - f.cx * f.cx;
	const double sxy = (s.xy[b] - s.xy[a]) / n - f.cx * f.cy;
	const double syy = (s.yy[b] - s.yy[a]) / n - f.cy * f.cy;
	// Direction of the larger eigenvalue: angle 0.5 atan2(2 sxy, sxx - syy); normal across it.
	const double t = 0.5 * std::atan2(2 * sxy, sxx - syy);
	f.nx = -std::sin(t), f.ny = std::cos(t);
	const double half = 0.5 * (sxx + syy), dev = std::hypot(0.5 * (sxx - syy), sxy);
	f.residual = std::max(0.0, half - dev);
	return f;
}
}  // namespace

double rangeNoiseStd(const mrpt::obs::CObservation2DRangeScan& obs)
{
	std::vector<double> d;
	const size_t n = obs.getScanSize();
	d.reserve(n);
	for (size_t i = 1; i + 1 < n; ++i)
	{
		if (!returned(obs, i - 1) || !returned(obs, i) || !returned(obs, i + 1)) continue;
		const double a = obs.getScanRange(i - 1), b = obs.getScanRange(i),
					 c = obs.getScanRange(i + 1);
		// A jump of more than kMaxSurfaceStep_m between neighbours is an edge (or a pane's
		// far side), not noise on one surface.
		if (std::abs(b - a) < kMaxSurfaceStep_m && std::abs(c - b) < kMaxSurfaceStep_m)
			d.push_back(std::abs(a - 2 * b + c));
	}
	if (d.size() < 10) return 0;
	// The lower quartile of |d| is 0.31864 sqrt(6) sigma for Gaussian noise.
	auto q = d.begin() + d.size() / 4;
	std::nth_element(d.begin(), q, d.end());
	return *q / (0.31864 * std::sqrt(6.0));
}

double CRangeNoiseEstimate::add(double scanSigma)
{
	if (scanSigma > 0)
	{
		m_recent.push_back(scanSigma);
		if (m_recent.size() > kWindow) m_recent.pop_front();
	}
	if (m_recent.empty()) return 0;
	std::vector<double> v(m_recent.begin(), m_recent.end());
	auto mid = v.begin() + v.size() / 2;
	std::nth_element(v.begin(), mid, v.end());
	return *mid;
}

std::vector<float> denoisedRanges(const mrpt::obs::CObservation2DRangeScan& obs, double sigma,
								  size_t* window)
{
	const double targetStd = kDenoiseTargetStd_m;
	const int maxHalfWindow = kDenoiseMaxHalfWindow;
	if (window) *window = 1;
	const size_t n = obs.getScanSize();
	std::vector<float> out(n);
	for (size_t i = 0; i < n; ++i) out[i] = obs.getScanRange(i);
	if (!(sigma > kNoisyLaserStd_m)) return out;
	const double ratio = sigma / targetStd;
	const size_t h =
		size_t(std::clamp(std::ceil((ratio * ratio - 1) / 2), 1.0, double(maxHalfWindow)));
	std::vector<size_t> ray;  // valid list index -> ray index
	TPrefixSums s;
	for (size_t i = 0; i < n; ++i)
		if (returned(obs, i))
		{
			const double r = obs.getScanRange(i), a = obs.getScanAngle(i);
			ray.push_back(i), s.add(r * std::cos(a), r * std::sin(a));
		}
	const size_t m = ray.size();
	if (m < 2 * h + 1) return out;
	if (window) *window = 2 * h + 1;
	for (size_t k = 0; k < m; ++k)
	{
		// The candidate windows [a, b) that hold 2h+1 returns including k.
		TLineFit best;
		best.residual = -1;
		const size_t starts[3] = {k >= h ? k - h : 0, k >= 2 * h ? k - 2 * h : 0, k};
		for (size_t a : starts)
		{
			a = std::min(a, m - (2 * h + 1));
			const TLineFit f = fitLine(s, a, a + 2 * h + 1);
			if (best.residual < 0 || f.residual < best.residual) best = f;
		}
		// Ray k: r u with u = (cos, sin); on the line where n . (r u - c) = 0.
		const double a = obs.getScanAngle(ray[k]);
		const double nu = best.nx * std::cos(a) + best.ny * std::sin(a);
		if (std::abs(nu) < 0.2) continue;
		const double r = (best.nx * best.cx + best.ny * best.cy) / nu;
		const double r0 = obs.getScanRange(ray[k]);
		if (r > 0 && std::abs(r - r0) <= 3 * sigma) out[ray[k]] = float(r);
	}
	return out;
}

}  // namespace lrgc
