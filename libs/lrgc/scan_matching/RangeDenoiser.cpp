#include <lrgc/scan_matching/RangeDenoiser.h>

#include <lrgc/common/OrderStatistic.h>
#include <lrgc/scan_matching/Scan.h>

#include <algorithm>
#include <cmath>

namespace lrgc
{
namespace
{
constexpr double kMaxSurfaceStep_m = 1.0;

/** Reading i, of range r, is a return. */
bool returned(const mrpt::obs::CObservation2DRangeScan& obs, size_t i, double r)
{
	return obs.getScanRangeValidity(i) && std::isfinite(r) && r > 0 && r < obs.maxRange;
}

/** Each reading's range, read once (MRPT's accessors are calls, and the loops below read each
 * reading up to three times). */
std::vector<float> rangesOf(const mrpt::obs::CObservation2DRangeScan& obs)
{
	std::vector<float> r(obs.getScanSize());
	for (size_t i = 0; i < r.size(); ++i) r[i] = obs.getScanRange(i);
	return r;
}

/** Prefix sums over the valid returns of c = cos(a), s = sin(a) (a: the beam's bearing) and
 * y = 1 / r (r: its range [m]), for O(1) window fits of a line in ray space. */
struct TPrefixSums
{
	std::vector<double> y1{0}, cc{0}, cs{0}, ss{0}, cy{0}, sy{0}, yy{0};
	void reserve(size_t n)
	{
		for (auto* v : {&y1, &cc, &cs, &ss, &cy, &sy, &yy}) v->reserve(n + 1);
	}
	void add(double c, double s, double y)
	{
		y1.push_back(y1.back() + y);
		cc.push_back(cc.back() + c * c), cs.push_back(cs.back() + c * s);
		ss.push_back(ss.back() + s * s), cy.push_back(cy.back() + c * y);
		sy.push_back(sy.back() + s * y), yy.push_back(yy.back() + y * y);
	}
};

/** A line n . p = d (sensor frame, d > 0) written as 1 / r(a) = A cos(a) + B sin(a) with
 * (A, B) = n / d [1/m]: the range it gives along every ray, and the mean squared residual of
 * the fit, in ranges [m^2]; valid is false where the fit is singular. */
struct TLineFit
{
	double A = 0, B = 0, residual = 0;
	bool valid = false;
};

/** Least-squares fit of 1 / r_i = A cos(a_i) + B sin(a_i) over returns [a, b) of the valid
 * list. The range noise lies along the rays, and so does this residual: a total-least-squares
 * line through the points instead assumes isotropic noise, and where the window's extent
 * along the wall (r times its angular span, 0.8 m at 2.5 m for 37 rays of 0.5 deg) is not
 * much larger than the noise (0.3 m) its direction is the noise's, and the projected ranges
 * were up to 3 sigma wrong (a 5 m corridor's side walls at 2.5 m). */
TLineFit fitLine(const TPrefixSums& s, size_t a, size_t b)
{
	const double cc = s.cc[b] - s.cc[a], cs = s.cs[b] - s.cs[a], ss = s.ss[b] - s.ss[a];
	const double cy = s.cy[b] - s.cy[a], sy = s.sy[b] - s.sy[a], yy = s.yy[b] - s.yy[a];
	const double det = cc * ss - cs * cs;
	TLineFit f;
	if (!(det > 1e-12 * (cc + ss) * (cc + ss))) return f;
	f.A = (ss * cy - cs * sy) / det, f.B = (cc * sy - cs * cy) / det;
	// A residual dy in 1 / r is dr = dy r^2 in range: scaled by the window's mean range (1 /
	// mean y) to the fourth power, windows near and far compare in metres.
	const double n = double(b - a), ybar = (s.y1[b] - s.y1[a]) / n;
	const double ybar2 = ybar * ybar;
	f.residual = std::max(0.0, (yy - f.A * cy - f.B * sy) / n) / (ybar2 * ybar2);
	f.valid = ybar > 0;
	return f;
}
/** The line through return k of the m valid ones: the window of 2h+1 returns centred on k if
 * its residual is what a single line with range noise sigma gives, below sigma^2 (1 + 3
 * sqrt(2 / (2h+1))) (the mean of a line's residual is about sigma^2, its std sigma^2 sqrt(2 /
 * n)); else the left or right window, the one with the smaller residual, if below that bound
 * (a one-sided window extrapolates to k with twice the centred one's error: picking the
 * smallest residual of the three on a flat wall, as before, took one two times in three, and
 * left range_030 with 79 unmatched scans, now 1). Else every window spans a corner or an edge:
 * a far wall narrower than the window (a 5 m corridor's end 21 m away spans 27 rays of 0.5
 * deg), whose fit across the corners would cut them and pull the wall nearer; then half the
 * window is tried, down to h = 1. Invalid if none fits. */
TLineFit lineAt(const TPrefixSums& s, size_t k, size_t h, double sigma)
{
	const size_t m = s.cc.size() - 1;
	for (;; h /= 2)
	{
		const double n = double(2 * h + 1);
		const double bound = sigma * sigma * (1 + 3 * std::sqrt(2 / n));
		const size_t starts[3] = {k >= h ? k - h : 0, k >= 2 * h ? k - 2 * h : 0, k};
		TLineFit best;
		for (size_t w = 0; w < 3; ++w)
		{
			const size_t a = std::min(starts[w], m - (2 * h + 1));
			const TLineFit f = fitLine(s, a, a + 2 * h + 1);
			if (w == 0 && f.valid && f.residual <= bound) return f;
			if (w > 0 && f.valid && (!best.valid || f.residual < best.residual)) best = f;
		}
		if (best.valid && best.residual <= bound) return best;
		if (h <= 1) return {};
	}
}
}  // namespace

double rangeNoiseStd(const mrpt::obs::CObservation2DRangeScan& obs)
{
	std::vector<double> d;
	const std::vector<float> r = rangesOf(obs);
	const size_t n = r.size();
	std::vector<char> ok(n);
	for (size_t i = 0; i < n; ++i) ok[i] = returned(obs, i, r[i]);
	d.reserve(n);
	for (size_t i = 1; i + 1 < n; ++i)
	{
		if (!ok[i - 1] || !ok[i] || !ok[i + 1]) continue;
		const double a = r[i - 1], b = r[i], c = r[i + 1];
		// A jump of more than kMaxSurfaceStep_m between neighbours is an edge (or a pane's
		// far side), not noise on one surface.
		if (std::abs(b - a) < kMaxSurfaceStep_m && std::abs(c - b) < kMaxSurfaceStep_m)
			d.push_back(std::abs(a - 2 * b + c));
	}
	if (d.size() < 10) return 0;
	// The lower quartile of |d| is 0.31864 sqrt(6) sigma for Gaussian noise.
	return kthSmallest(d, d.size() / 4) / (0.31864 * std::sqrt(6.0));
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
	return upperMedian(v);
}

std::vector<float> denoisedRanges(const mrpt::obs::CObservation2DRangeScan& obs, double sigma,
								  size_t* window)
{
	const double targetStd = kDenoiseTargetStd_m;
	const int maxHalfWindow = kDenoiseMaxHalfWindow;
	if (window) *window = 1;
	const std::vector<float> measured = rangesOf(obs);
	std::vector<float> out = measured;
	const size_t n = out.size();
	if (!(sigma > kNoisyLaserStd_m)) return out;
	const double ratio = sigma / targetStd;
	const size_t h =
		size_t(std::clamp(std::ceil((ratio * ratio - 1) / 2), 1.0, double(maxHalfWindow)));
	const TBeamDirections& beams = beamDirections(obs);
	std::vector<size_t> ray;  // valid list index -> ray index
	ray.reserve(n);
	TPrefixSums s;
	s.reserve(n);
	for (size_t i = 0; i < n; ++i)
		if (returned(obs, i, measured[i]))
			ray.push_back(i), s.add(beams.cos[i], beams.sin[i], 1.0 / measured[i]);
	const size_t m = ray.size();
	if (m < 2 * h + 1) return out;
	if (window) *window = 2 * h + 1;
	for (size_t k = 0; k < m; ++k)
	{
		const TLineFit best = lineAt(s, k, h, sigma);
		if (!best.valid) continue;
		// Ray k meets the line at 1 / r = A cos + B sin; |cos| of the incidence is that over
		// |(A, B)|. The fit of 1 / r is biased: E[1 / (r + e)] = (1 + sigma^2 / r^2) / r to
		// second order for range noise e of std sigma, so r = rf + sigma^2 / rf corrects the
		// fitted rf (0.036 m at 2.5 m for sigma = 0.3 m).
		const size_t i = ray[k];
		const double inv = best.A * beams.cos[i] + best.B * beams.sin[i];
		if (!(inv > 0) || inv < 0.2 * std::hypot(best.A, best.B)) continue;
		const double rf = 1.0 / inv, r = rf + sigma * sigma / rf;
		const double r0 = measured[i];
		if (std::abs(r - r0) <= 3 * sigma) out[ray[k]] = float(r);
	}
	return out;
}

}  // namespace lrgc
