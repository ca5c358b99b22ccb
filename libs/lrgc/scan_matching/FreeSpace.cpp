#include <lrgc/scan_matching/FreeSpace.h>

#include <lrgc/common/se2.h>
#include <lrgc/scan_matching/Scan.h>

#include <algorithm>
#include <cmath>

namespace lrgc
{
namespace
{
constexpr double kFreeSpaceBin_rad = M_PI / 180;  // [rad] bearing bins of the range images (1 deg)
constexpr size_t kFreeSpaceBins = 361;  // bins over (-pi, pi]
/** [m] Violating scan points count only with a violating neighbour in scan order this close. */
constexpr double kWallGap_m = 0.3;
}  // namespace

CRangeImage::CRangeImage(const std::vector<Eigen::Vector2d>& pts)
	: m_minRange(kFreeSpaceBins, 0.0f)
{
	auto& m = m_minRange;
	for (const auto& q : pts)
	{
		const auto b = std::min(kFreeSpaceBins - 1, static_cast<size_t>((std::atan2(q.y(), q.x()) + M_PI) / kFreeSpaceBin_rad));
		const auto r = static_cast<float>(q.norm());
		if (m[b] == 0 || r < m[b]) m[b] = r;
	}
	for (size_t b = 1; b + 1 < m.size(); ++b)
		if (m[b] == 0 && m[b - 1] > 0 && m[b + 1] > 0) m[b] = std::min(m[b - 1], m[b + 1]);
}

bool CRangeImage::inFreeSpace(const Eigen::Vector2d& d, double margin, bool* known) const
{
	const long n = static_cast<long>(m_minRange.size());
	const auto b = static_cast<long>((std::atan2(d.y(), d.x()) + M_PI) / kFreeSpaceBin_rad);
	float f = 1e9f;
	for (long k = b - 1; k <= b + 1; ++k) f = std::min(f, m_minRange[static_cast<size_t>((k + n) % n)]);
	if (known) *known = f > 0;
	return d.norm() < f - margin;
}

void CFreeSpaceViews::add(const TScan2D& scan, const mrpt::math::TPose2D& scanInRef)
{
	m_views.push_back({scanInRef, CRangeImage(scan.points)});
}

double CFreeSpaceViews::scanViolation(
	const TScan2D& scan, const mrpt::math::TPose2D& scanInRef, double margin) const
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
		inRef[i] = Eigen::Vector2d(
			scanInRef.x + c0 * pts[i].x() - s0 * pts[i].y(), scanInRef.y + s0 * pts[i].x() + c0 * pts[i].y());
		for (size_t k = 0; k < m_views.size(); ++k)
			if (m_views[k].image.inFreeSpace(toView[k].first * inRef[i] + toView[k].second, margin))
			{
				viol[i] = 1;
				break;
			}
	}
	size_t count = 0;
	for (size_t i = 0; i < pts.size(); ++i)
	{
		const bool prev = i > 0 && viol[i - 1] && (inRef[i] - inRef[i - 1]).norm() < kWallGap_m;
		const bool next = i + 1 < pts.size() && viol[i + 1] && (inRef[i] - inRef[i + 1]).norm() < kWallGap_m;
		count += viol[i] && (prev || next);
	}
	return static_cast<double>(count) / pts.size();
}

}  // namespace lrgc
