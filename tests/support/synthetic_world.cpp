/* The synthetic world (synthetic_world.h): segments and their surfaces, ray and beam
 * casting, the simulated laser and free-pose sampling. The world builders are in
 * synthetic_world_builders.cpp, the trajectories and odometry in
 * synthetic_world_trajectory.cpp. */
#include "synthetic_world.h"

#include <lrgc/common/se2.h>
#include <mrpt/core/exceptions.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace lrgc::test
{
namespace
{
double cross2(const Eigen::Vector2d& u, const Eigen::Vector2d& v)
{
	return u.x() * v.y() - u.y() * v.x();
}
}  // namespace

void CSyntheticWorld::addSegment(const Eigen::Vector2d& a, const Eigen::Vector2d& b)
{
	m_segments.push_back({a, b});
}

void CSyntheticWorld::addPolygon(const std::vector<Eigen::Vector2d>& v)
{
	for (size_t i = 0; i < v.size(); ++i) addSegment(v[i], v[(i + 1) % v.size()]);
}

void CSyntheticWorld::addBox(const Eigen::Vector2d& c, double hx, double hy, double angle)
{
	const Eigen::Rotation2Dd R(angle);
	addPolygon({c + R * Eigen::Vector2d(-hx, -hy), c + R * Eigen::Vector2d(hx, -hy),
				c + R * Eigen::Vector2d(hx, hy), c + R * Eigen::Vector2d(-hx, hy)});
}

void CSyntheticWorld::addCircle(const Eigen::Vector2d& c, double radius, int sides)
{
	std::vector<Eigen::Vector2d> v;
	for (int i = 0; i < sides; ++i)
	{
		const double a = 2 * M_PI * i / sides;
		v.emplace_back(c + radius * Eigen::Vector2d(std::cos(a), std::sin(a)));
	}
	addPolygon(v);
}

void CSyntheticWorld::addWorld(const CSyntheticWorld& other, const Eigen::Vector2d& offset)
{
	for (const auto& s : other.m_segments) addSegment(s.a + offset, s.b + offset);
}

TBox CSyntheticWorld::bounds() const
{
	TBox b;
	if (m_segments.empty()) return b;
	b.min = b.max = m_segments.front().a;
	for (const auto& s : m_segments)
	{
		b.min = b.min.cwiseMin(s.a).cwiseMin(s.b);
		b.max = b.max.cwiseMax(s.a).cwiseMax(s.b);
	}
	return b;
}

void CSyntheticWorld::addGlass(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
							   double returnRate)
{
	ASSERT_(returnRate >= 0 && returnRate <= 1);
	m_segments.push_back({a, b, TSurface::Glass, returnRate, 0, 0});
}

void CSyntheticWorld::addRailing(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
								 double spacing, double diameter)
{
	ASSERT_(spacing > diameter && diameter > 0);
	m_segments.push_back({a, b, TSurface::Railing, 1, spacing, diameter});
}

bool CSyntheticWorld::hasSeeThrough() const
{
	return std::any_of(m_segments.begin(), m_segments.end(),
					   [](const TSegment& s) { return s.surface != TSurface::Solid; });
}

namespace
{
/** The first post of railing `seg` that the ray o + t d (|d| = 1) meets, given where the ray
 * crosses the railing's line (s in [0, 1] along it). Posts are discs of radius rho at
 * a + k * spacing * u; one at along-offset delta from the crossing is delta * sin(theta) from
 * the ray (theta: ray to railing), so only |delta| < rho / sin(theta) can be hit; a hit one
 * is met at t = (c - o).d - sqrt(rho^2 - perp^2). */
std::optional<TBeamHit> railingHit(const TSegment& seg, const Eigen::Vector2d& o,
								   const Eigen::Vector2d& d, double s)
{
	const Eigen::Vector2d e = seg.b - seg.a;
	const double len = e.norm(), rho = seg.postDiameter / 2;
	const Eigen::Vector2d u = e / len;
	const double sinTheta = std::max(std::abs(cross2(d, u)), 1e-3);
	const double reach = std::min(rho / sinTheta, 50 * seg.postSpacing);
	const long last = static_cast<long>(std::floor(len / seg.postSpacing));
	const long k0 =
		std::max(0L, static_cast<long>(std::ceil((s * len - reach) / seg.postSpacing)));
	const long k1 =
		std::min(last, static_cast<long>(std::floor((s * len + reach) / seg.postSpacing)));
	std::optional<TBeamHit> best;
	for (long k = k0; k <= k1; ++k)
	{
		const Eigen::Vector2d c = seg.a + double(k) * seg.postSpacing * u;
		const double perp = cross2(d, c - o), tc = (c - o).dot(d);
		if (std::abs(perp) >= rho) continue;
		const double t = tc - std::sqrt(rho * rho - perp * perp);
		if (t <= 1e-9 || (best && t >= best->range)) continue;
		const Eigen::Vector2d normal = (o + t * d - c) / rho;
		best = TBeamHit{t, std::abs(normal.dot(d))};
	}
	return best;
}
}  // namespace

std::optional<double> CSyntheticWorld::castRay(const Eigen::Vector2d& o, double angle,
											   double maxRange) const
{
	const auto hit = castBeam(o, angle, maxRange, 0.0);
	if (!hit) return std::nullopt;
	return hit->range;
}

std::optional<TBeamHit> CSyntheticWorld::castBeam(const Eigen::Vector2d& o, double angle,
												  double maxRange, double glassDraw) const
{
	// Ray o + t d (t > 0) against segment a + s e (0 <= s <= 1):
	// t = cross(a - o, e) / cross(d, e), s = cross(a - o, d) / cross(d, e).
	// Crossings are visited nearest first; a solid one ends the ray, glass and railings may
	// let it through.
	const Eigen::Vector2d d(std::cos(angle), std::sin(angle));
	struct TCrossing
	{
		double t, s;
		const TSegment* seg;
	};
	std::vector<TCrossing> crossings;
	for (const auto& seg : m_segments)
	{
		const Eigen::Vector2d e = seg.b - seg.a;
		const double den = cross2(d, e);
		if (std::abs(den) < 1e-12) continue;
		const Eigen::Vector2d w = seg.a - o;
		const double t = cross2(w, e) / den, s = cross2(w, d) / den;
		if (t > 1e-9 && t < maxRange && s >= 0 && s <= 1) crossings.push_back({t, s, &seg});
	}
	std::sort(crossings.begin(), crossings.end(),
			  [](const TCrossing& x, const TCrossing& y) { return x.t < y.t; });
	for (const auto& c : crossings)
	{
		const TSegment& seg = *c.seg;
		if (seg.surface == TSurface::Glass && glassDraw >= seg.glassReturn) continue;
		if (seg.surface == TSurface::Railing)
		{
			const auto post = railingHit(seg, o, d, c.s);
			if (post && post->range < maxRange) return post;
			continue;
		}
		const Eigen::Vector2d e = (seg.b - seg.a).normalized();
		return TBeamHit{c.t, std::abs(cross2(d, e))};
	}
	return std::nullopt;
}

namespace
{
/** Euclidean distance [m] from p to segment seg. */
double distanceTo(const TSegment& seg, const Eigen::Vector2d& p)
{
	const Eigen::Vector2d e = seg.b - seg.a;
	const double L2 = e.squaredNorm();
	const double s = L2 > 0 ? std::clamp((p - seg.a).dot(e) / L2, 0.0, 1.0) : 0.0;
	return (seg.a + s * e - p).norm();
}
}  // namespace

double CSyntheticWorld::distanceToNearest(const Eigen::Vector2d& p) const
{
	double best = std::numeric_limits<double>::infinity();
	for (const auto& seg : m_segments) best = std::min(best, distanceTo(seg, p));
	return best;
}

CSyntheticWorld CSyntheticWorld::within(const Eigen::Vector2d& origin, double range) const
{
	constexpr double kRounding = 1e-3;  // [m]
	CSyntheticWorld near;
	for (const auto& seg : m_segments)
		if (distanceTo(seg, origin) < range + kRounding) near.m_segments.push_back(seg);
	return near;
}

namespace
{
/** The range [m] one beam reads, with the mixed-return effects of `laser` (see
 * TLaserSimParams): draws are (glass, mixed pixel?, where between, max-range dropout). */
std::optional<double> mixedReturn(const CSyntheticWorld& world, const Eigen::Vector2d& origin,
								  double angle, const TLaserSimParams& laser,
								  const std::array<double, 4>& draw)
{
	const auto hit = world.castBeam(origin, angle, laser.maxRange, draw[0]);
	if (!hit) return std::nullopt;
	const double dropout =
		laser.maxRangeDropRate * (hit->range / laser.maxRange + 1 - hit->cosIncidence);
	if (draw[3] < dropout) return std::nullopt;
	if (draw[1] >= laser.mixedPixelRate) return hit->range;
	// The spot's two edges, with the beam's own glass draw.
	const double half = laser.footprint_deg * M_PI / 360;
	const auto left = world.castBeam(origin, angle - half, laser.maxRange, draw[0]);
	const auto right = world.castBeam(origin, angle + half, laser.maxRange, draw[0]);
	if (!left || !right || std::abs(left->range - right->range) <= 0.1) return hit->range;
	const double nearR = std::min(left->range, right->range);
	const double farR = std::max(left->range, right->range);
	return nearR + draw[2] * (farR - nearR);
}
}  // namespace

lrgc::TScan2D simulateScan(const CSyntheticWorld& world,
						   const mrpt::math::TPose2D& robotInWorld,
						   const TLaserSimParams& laser, std::mt19937& rng)
{
	ASSERT_GE_(laser.beams, 2);
	lrgc::TScan2D scan;
	scan.maxRange = laser.maxRange;
	const auto sensorInWorld = lrgc::compose(robotInWorld, laser.sensorInRobot);
	const Eigen::Vector2d origin(sensorInWorld.x, sensorInWorld.y);
	const double fov = laser.fov_deg * M_PI / 180;
	// Whether the beams draw the mixed-return numbers is the whole world's property, not the
	// nearby segments'.
	const bool mixed =
		world.hasSeeThrough() || laser.mixedPixelRate > 0 || laser.maxRangeDropRate > 0;
	const CSyntheticWorld near = world.within(origin, laser.maxRange);
	std::normal_distribution<double> noise(0.0, laser.rangeNoiseStd);
	std::uniform_real_distribution<double> u01(0.0, 1.0);
	for (int i = 0; i < laser.beams; ++i)
	{
		const double a = -fov / 2 + fov * i / (laser.beams - 1);  // sensor frame [rad]
		// Draw every random number for every beam, so that changing one rate does not
		// reshuffle the noise of the other beams.
		const double n = noise(rng), uOut = u01(rng), uOutR = u01(rng), uDrop = u01(rng);
		std::array<double, 4> draw{0, 1, 0, 1};
		if (mixed)
			for (auto& x : draw) x = u01(rng);
		const auto r0 = mixed ? mixedReturn(near, origin, sensorInWorld.phi + a, laser, draw)
							  : near.castRay(origin, sensorInWorld.phi + a, laser.maxRange);
		if (!r0 || uDrop < laser.dropRate) continue;
		double r = *r0 + n;
		if (uOut < laser.outlierRate) r = laser.minRange + uOutR * (*r0 - laser.minRange);
		if (r < laser.minRange || r >= laser.maxRange) continue;
		const Eigen::Vector2d pSensor(r * std::cos(a), r * std::sin(a));
		scan.points.push_back(lrgc::transformPoint(laser.sensorInRobot, pSensor));
	}
	return scan;
}

void removeBearingSector(lrgc::TScan2D& scan, double from_rad, double to_rad)
{
	auto& pts = scan.points;
	pts.erase(std::remove_if(pts.begin(), pts.end(),
							 [&](const Eigen::Vector2d& p)
							 {
								 const double b = std::atan2(p.y(), p.x());
								 return b >= from_rad && b <= to_rad;
							 }),
			  pts.end());
	scan.rangeImage.reset();  // of the points before
}

std::optional<mrpt::math::TPose2D> sampleFreePose(const CSyntheticWorld& world,
												  const TBox& region, double clearance,
												  std::mt19937& rng)
{
	std::uniform_real_distribution<double> ux(region.min.x(), region.max.x()),
		uy(region.min.y(), region.max.y()), ua(-M_PI, M_PI);
	for (int k = 0; k < 1000; ++k)
	{
		const Eigen::Vector2d p(ux(rng), uy(rng));
		const double phi = ua(rng);
		if (world.distanceToNearest(p) >= clearance)
			return mrpt::math::TPose2D(p.x(), p.y(), phi);
	}
	return std::nullopt;
}
}  // namespace lrgc::test
