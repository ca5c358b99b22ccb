#include <lrgc/scan_matching/FreeSpace.h>

#include <lrgc/common/se2.h>
#include <lrgc/scan_matching/Scan.h>

#include <algorithm>
#include <cmath>

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

/** Unit vectors of the bin borders, angle b bin - pi for b = 0..360. */
struct TBinBorders
{
	double c[kFreeSpaceBins], s[kFreeSpaceBins];
	TBinBorders()
	{
		for (size_t b = 0; b < kFreeSpaceBins; ++b)
			c[b] = std::cos(b * kFreeSpaceBin_rad - M_PI),
			s[b] = std::sin(b * kFreeSpaceBin_rad - M_PI);
	}
};
}  // namespace

long bearingBin(double x, double y)
{
	// A rough bearing (atan on [0, 1] as z (pi/4 + 0.273 (1 - z)), error < 0.004 rad, a
	// quarter of a bin) gives a candidate bin; the signs of the cross products of (x, y) with
	// the borders of that bin or of a neighbour settle it when (x, y) is clear of the
	// borders by 1e-9 rad, far more than the rounding of exactBin (~1e-13 rad). Near a
	// border, at +-pi, or at the origin, exactBin decides.
	static const TBinBorders borders;
	const double ax = std::abs(x), ay = std::abs(y);
	if (!(ax > 0 || ay > 0) || !std::isfinite(ax + ay)) return exactBin(x, y);
	const double z = ax >= ay ? ay / ax : ax / ay;
	double a = z * (M_PI / 4 + 0.273 * (1 - z));
	if (ax < ay) a = M_PI / 2 - a;
	if (x < 0) a = M_PI - a;
	if (y < 0) a = -a;
	const long b0 = static_cast<long>((a + M_PI) / kFreeSpaceBin_rad);
	if (b0 < 2 || b0 > 357) return exactBin(x, y);
	const double eps = 1e-9 * (ax + ay);  // >= 1e-9 rad times |(x, y)|
	auto cross = [&](long b)
	{ return borders.c[b] * y - borders.s[b] * x; };  // |d| sin(d - border)
	for (long b = b0 - 1; b <= b0 + 1; ++b)
	{
		const double lo = cross(b), hi = cross(b + 1);
		if (lo > eps && hi < -eps) return b;
	}
	return exactBin(x, y);
}

CRangeImage::CRangeImage(const std::vector<Eigen::Vector2d>& pts)
	: m_minRange(kFreeSpaceBins, 0.0f)
{
	auto& m = m_minRange;
	for (const auto& q : pts)
	{
		const auto b =
			std::min(kFreeSpaceBins - 1, static_cast<size_t>(bearingBin(q.x(), q.y())));
		const auto r = static_cast<float>(q.norm());
		if (m[b] == 0 || r < m[b]) m[b] = r;
	}
	for (size_t b = 1; b + 1 < m.size(); ++b)
		if (m[b] == 0 && m[b - 1] > 0 && m[b + 1] > 0) m[b] = std::min(m[b - 1], m[b + 1]);
}

bool CRangeImage::inFreeSpace(const Eigen::Vector2d& d, double margin, bool* known) const
{
	const long n = static_cast<long>(m_minRange.size());
	const long b = bearingBin(d.x(), d.y());
	float f = 1e9f;
	for (long k = b - 1; k <= b + 1; ++k)
		f = std::min(f, m_minRange[static_cast<size_t>((k + n) % n)]);
	if (known) *known = f > 0;
	return d.norm() < f - margin;
}

void CFreeSpaceViews::add(const TScan2D& scan, const mrpt::math::TPose2D& scanInRef)
{
	m_views.push_back({scanInRef, CRangeImage(scan.points)});
}

bool CFreeSpaceViews::seenThrough(const Eigen::Vector2d& p, double margin) const
{
	for (const auto& v : m_views)
		if (v.image.inFreeSpace(transformPoint(inverse(v.scanInRef), p), margin)) return true;
	return false;
}

double CFreeSpaceViews::scanViolation(const TScan2D& scan, const mrpt::math::TPose2D& scanInRef,
									  double margin) const
{
	const auto& pts = scan.points;
	if (pts.empty() || m_views.empty()) return 0;
	std::vector<char> viol(pts.size(), 0);
	std::vector<Eigen::Vector2d> inRef(pts.size());
	// (view <- ref) as rotation + translation, computed once per view.
	std::vector<std::pair<Eigen::Matrix2d, Eigen::Vector2d>> toView;
	for (const auto& v : m_views)
	{
		const auto inv = inverse(v.scanInRef);
		const double c = std::cos(inv.phi), s = std::sin(inv.phi);
		toView.push_back({(Eigen::Matrix2d() << c, -s, s, c).finished(), {inv.x, inv.y}});
	}
	const double c0 = std::cos(scanInRef.phi), s0 = std::sin(scanInRef.phi);
	for (size_t i = 0; i < pts.size(); ++i)
	{
		inRef[i] = Eigen::Vector2d(scanInRef.x + c0 * pts[i].x() - s0 * pts[i].y(),
								   scanInRef.y + s0 * pts[i].x() + c0 * pts[i].y());
		for (size_t k = 0; k < m_views.size(); ++k)
			if (m_views[k].image.inFreeSpace(toView[k].first * inRef[i] + toView[k].second,
											 margin))
			{
				viol[i] = 1;
				break;
			}
	}
	size_t count = 0;
	for (size_t i = 0; i < pts.size(); ++i)
	{
		const bool prev = i > 0 && viol[i - 1] && (inRef[i] - inRef[i - 1]).norm() < kWallGap_m;
		const bool next =
			i + 1 < pts.size() && viol[i + 1] && (inRef[i] - inRef[i + 1]).norm() < kWallGap_m;
		count += viol[i] && (prev || next);
	}
	return static_cast<double>(count) / pts.size();
}

}  // namespace lrgc
