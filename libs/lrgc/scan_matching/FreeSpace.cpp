#include <lrgc/scan_matching/FreeSpace.h>

#include <lrgc/common/se2.h>
#include <lrgc/scan_matching/Scan.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace lrgc
{
namespace
{
constexpr double kFreeSpaceBin_rad =
	M_PI / 180;                         // [rad] bearing bins of the range images (1 deg)
constexpr size_t kFreeSpaceBins = 361;  // bins over (-pi, pi]
/** [m] Violating scan points count only with a violating neighbour in scan order this close. */
constexpr double kWallGap_m = 0.3;

/** The exact bin formula: (atan2(y, x) + pi) / bin, truncated. */
long exactBin(double x, double y)
{
	return static_cast<long>((std::atan2(y, x) + M_PI) / kFreeSpaceBin_rad);
}

/** [rad] Bound on |bearingApprox - atan2|: A&S 4.4.49's error, 1.149e-5 rad at its 7-digit
 * coefficients (measured on 10^8 points of [0, 1], the error's slope below 0.0013, so 1e-11
 * between points), plus the rounding of its evaluation (~1e-15), with room to spare. */
constexpr double kApproxError_rad = 2e-5;

/** atan2(y, x) for finite (x, y) != (0, 0), within kApproxError_rad: atan of the smaller
 * over the larger |coordinate| (z in [0, 1]) as the odd polynomial of Abramowitz & Stegun
 * 4.4.49, then the octant's reflections. */
double bearingApprox(double x, double y)
{
	const double ax = std::abs(x), ay = std::abs(y);
	const double z = ax >= ay ? ay / ax : ax / ay, z2 = z * z;
	double a = z * (0.9998660 +
					z2 * (-0.3302995 + z2 * (0.1801410 + z2 * (-0.0851330 + z2 * 0.0208351))));
	if (ax < ay) a = M_PI / 2 - a;
	if (x < 0) a = M_PI - a;
	if (y < 0) a = -a;
	return a;
}
}  // namespace

long bearingBin(double x, double y)
{
	// t = (bearing + pi) / bin from bearingApprox is within kApproxError_rad / bin (0.0012)
	// of the exact (atan2(y, x) + pi) / bin, and exactBin's own rounding (~1e-13) is far
	// below that: where t is farther than that from an integer, both truncate to the same
	// bin. Near a border (0.23 % of directions), at the origin or off the finite plane,
	// exactBin decides.
	constexpr double kMarginBins = kApproxError_rad / kFreeSpaceBin_rad;
	const double ax = std::abs(x), ay = std::abs(y);
	if (!(ax > 0 || ay > 0) || !std::isfinite(ax + ay)) return exactBin(x, y);
	const double t = (bearingApprox(x, y) + M_PI) * (1 / kFreeSpaceBin_rad);
	const long b = static_cast<long>(t);
	const double frac = t - static_cast<double>(b);
	if (frac > kMarginBins && frac < 1 - kMarginBins) return b;
	return exactBin(x, y);
}

CRangeImage::CRangeImage(const std::vector<Eigen::Vector2d>& pts) : m_numPoints(pts.size())
{
	std::vector<float> m(kFreeSpaceBins, 0.0f);
	for (const auto& q : pts)
	{
		const auto b =
			std::min(kFreeSpaceBins - 1, static_cast<size_t>(bearingBin(q.x(), q.y())));
		const auto r = static_cast<float>(q.norm());
		if (m[b] == 0 || r < m[b]) m[b] = r;
	}
	for (size_t b = 1; b + 1 < m.size(); ++b)
		if (m[b] == 0 && m[b - 1] > 0 && m[b + 1] > 0) m[b] = std::min(m[b - 1], m[b + 1]);
	// Each bin's neighbourhood (b - 1, b, b + 1, wrapping around) reduced once here rather
	// than at every inFreeSpace call (the same minimum: min is exact).
	const size_t n = m.size();
	m_nearest3.resize(n);
	for (size_t b = 0; b < n; ++b)
		m_nearest3[b] = std::min({1e9f, m[(b + n - 1) % n], m[b], m[(b + 1) % n]});
}

bool CRangeImage::inFreeSpace(const Eigen::Vector2d& d, double margin, bool* known) const
{
	const float f = m_nearest3[static_cast<size_t>(bearingBin(d.x(), d.y()))];
	if (known) *known = f > 0;
	return d.norm() < f - margin;
}

std::pair<double, double> CRangeImage::medianChange(const CRangeImage& other) const
{
	std::vector<float> change;
	change.reserve(m_nearest3.size());
	size_t either = 0;
	for (size_t b = 0; b < m_nearest3.size(); ++b)
	{
		const float r = m_nearest3[b], o = other.m_nearest3[b];
		either += r > 0 || o > 0;
		if (r > 0 && o > 0) change.push_back(std::abs(o - r));
	}
	if (change.empty()) return {std::numeric_limits<double>::infinity(), 0.0};
	auto mid = change.begin() + change.size() / 2;
	std::nth_element(change.begin(), mid, change.end());
	return {*mid, double(change.size()) / double(either)};
}

std::shared_ptr<const CRangeImage> rangeImageOf(const TScan2D& scan)
{
	if (scan.rangeImage && scan.rangeImage->numPoints() == scan.points.size())
		return scan.rangeImage;
	return std::make_shared<const CRangeImage>(scan.points);
}

void CFreeSpaceViews::add(const TScan2D& scan, const mrpt::math::TPose2D& scanInRef)
{
	m_views.push_back({scanInRef, rangeImageOf(scan)});
}

bool CFreeSpaceViews::seenThrough(const Eigen::Vector2d& p, double margin) const
{
	for (const auto& v : m_views)
		if (v.image->inFreeSpace(transformPoint(inverse(v.scanInRef), p), margin)) return true;
	return false;
}

double CFreeSpaceViews::scanViolation(const TScan2D& scan, const mrpt::math::TPose2D& scanInRef,
									  double margin) const
{
	CScanViolation v(*this, scan, scanInRef, margin);
	v.flag(0, v.size());
	return v.share();
}

CScanViolation::CScanViolation(const CFreeSpaceViews& views, const TScan2D& scan,
							   const mrpt::math::TPose2D& scanInRef, double margin)
	: m_views(views),
	  m_pts(scan.points),
	  m_margin(margin),
	  m_c0(std::cos(scanInRef.phi)),
	  m_s0(std::sin(scanInRef.phi)),
	  m_scanInRef(scanInRef)
{
	if (m_pts.empty() || views.m_views.empty()) return;  // size() 0: share() is 0
	m_viol.assign(m_pts.size(), 0);
	m_inRef.resize(m_pts.size());
	for (const auto& v : views.m_views)
	{
		const auto inv = inverse(v.scanInRef);
		const double c = std::cos(inv.phi), s = std::sin(inv.phi);
		m_toView.push_back({(Eigen::Matrix2d() << c, -s, s, c).finished(), {inv.x, inv.y}});
	}
}

void CScanViolation::flag(size_t begin, size_t end)
{
	const auto& views = m_views.m_views;
	for (size_t i = begin; i < end; ++i)
	{
		m_inRef[i] = Eigen::Vector2d(m_scanInRef.x + m_c0 * m_pts[i].x() - m_s0 * m_pts[i].y(),
									 m_scanInRef.y + m_s0 * m_pts[i].x() + m_c0 * m_pts[i].y());
		for (size_t k = 0; k < views.size(); ++k)
			if (views[k].image->inFreeSpace(m_toView[k].first * m_inRef[i] + m_toView[k].second,
											m_margin))
			{
				m_viol[i] = 1;
				break;
			}
	}
}

double CScanViolation::share(double minRun_m) const
{
	const size_t n = m_viol.size();
	if (n == 0) return 0;
	if (minRun_m > 0) return longRunsShare(minRun_m);
	size_t count = 0;
	for (size_t i = 0; i < n; ++i)
	{
		const bool prev =
			i > 0 && m_viol[i - 1] && (m_inRef[i] - m_inRef[i - 1]).norm() < kWallGap_m;
		const bool next =
			i + 1 < n && m_viol[i + 1] && (m_inRef[i] - m_inRef[i + 1]).norm() < kWallGap_m;
		count += m_viol[i] && (prev || next);
	}
	return static_cast<double>(count) / n;
}

double CScanViolation::longRunsShare(double minRun_m) const
{
	const size_t n = m_viol.size();
	size_t count = 0;
	for (size_t i = 0; i < n;)
	{
		if (!m_viol[i])
		{
			++i;
			continue;
		}
		// [i, j): a run of flagged points, each within kWallGap_m of the last; it counts with
		// two points at least (share()'s flagged neighbour), spanning minRun_m end to end.
		size_t j = i + 1;
		while (j < n && m_viol[j] && (m_inRef[j] - m_inRef[j - 1]).norm() < kWallGap_m) ++j;
		if (j - i >= 2 && (m_inRef[j - 1] - m_inRef[i]).norm() >= minRun_m) count += j - i;
		i = j;
	}
	return static_cast<double>(count) / n;
}

}  // namespace lrgc
