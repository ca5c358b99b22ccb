#include "synthetic_world.h"

#include <lrgc/common/se2.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/math/wrap2pi.h>

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

double CSyntheticWorld::distanceToNearest(const Eigen::Vector2d& p) const
{
	double best = std::numeric_limits<double>::infinity();
	for (const auto& seg : m_segments)
	{
		const Eigen::Vector2d e = seg.b - seg.a;
		const double L2 = e.squaredNorm();
		const double s = L2 > 0 ? std::clamp((p - seg.a).dot(e) / L2, 0.0, 1.0) : 0.0;
		best = std::min(best, (seg.a + s * e - p).norm());
	}
	return best;
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
	const bool mixed =
		world.hasSeeThrough() || laser.mixedPixelRate > 0 || laser.maxRangeDropRate > 0;
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
		const auto r0 = mixed ? mixedReturn(world, origin, sensorInWorld.phi + a, laser, draw)
							  : world.castRay(origin, sensorInWorld.phi + a, laser.maxRange);
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

CSyntheticWorld makeRoomWorld(uint32_t seed, int clutter)
{
	CSyntheticWorld w;
	// Outer walls with a 1 m doorway in the top wall (x in [4, 5]).
	w.addSegment({0, 0}, {10, 0});
	w.addSegment({10, 0}, {10, 7});
	w.addSegment({10, 7}, {5, 7});
	w.addSegment({4, 7}, {0, 7});
	w.addSegment({0, 7}, {0, 0});
	// A short corridor stub behind the doorway.
	w.addSegment({4, 7}, {4, 9});
	w.addSegment({5, 7}, {5, 9});
	// Pillars and an L-shaped counter.
	w.addBox({3, 2}, 0.3, 0.3);
	w.addCircle({7, 5}, 0.25);
	w.addSegment({6, 1}, {8.5, 1});
	w.addSegment({8.5, 1}, {8.5, 2.5});
	// Seeded clutter: short segments at random places and angles.
	std::mt19937 rng(seed);
	std::uniform_real_distribution<double> ux(1, 9), uy(1, 6), ua(-M_PI, M_PI), ul(0.2, 0.6);
	for (int i = 0; i < clutter; ++i)
	{
		const Eigen::Vector2d c(ux(rng), uy(rng));
		const double a = ua(rng), half = ul(rng) / 2;
		const Eigen::Vector2d d(std::cos(a) * half, std::sin(a) * half);
		w.addSegment(c - d, c + d);
	}
	return w;
}

CSyntheticWorld makeCorridorWorld(double length, double width)
{
	CSyntheticWorld w;
	w.addSegment({0, 0}, {length, 0});
	w.addSegment({0, width}, {length, width});
	return w;
}

CSyntheticWorld makeRepeatedRoomsWorld(int nx, int ny, double s, double door)
{
	ASSERT_(nx >= 1 && ny >= 1 && s > door && door >= 0);
	CSyntheticWorld w;
	const double g0 = (s - door) / 2, g1 = (s + door) / 2;  // door gap within a wall
	// Vertical walls x = i*s; interior ones get a doorway per room.
	for (int i = 0; i <= nx; ++i)
		for (int j = 0; j < ny; ++j)
		{
			const double x = i * s, y = j * s;
			if (i == 0 || i == nx)
			{
				w.addSegment({x, y}, {x, y + s});
				continue;
			}
			w.addSegment({x, y}, {x, y + g0});
			w.addSegment({x, y + g1}, {x, y + s});
		}
	for (int j = 0; j <= ny; ++j)
		for (int i = 0; i < nx; ++i)
		{
			const double x = i * s, y = j * s;
			if (j == 0 || j == ny)
			{
				w.addSegment({x, y}, {x + s, y});
				continue;
			}
			w.addSegment({x, y}, {x + g0, y});
			w.addSegment({x + g1, y}, {x + s, y});
		}
	// Identical, asymmetric furniture in every room.
	for (int i = 0; i < nx; ++i)
		for (int j = 0; j < ny; ++j)
		{
			const Eigen::Vector2d o(i * s, j * s);
			w.addBox(o + Eigen::Vector2d(0.3 * s, 0.3 * s), 0.4, 0.25, 0.3);
			w.addCircle(o + Eigen::Vector2d(0.7 * s, 0.65 * s), 0.2, 12);
			w.addSegment(o + Eigen::Vector2d(0.75 * s, 0.2 * s),
						 o + Eigen::Vector2d(0.9 * s, 0.2 * s));
		}
	return w;
}

CSyntheticWorld makeOpenHallWorld(uint32_t seed, double L, double W, int alcoves)
{
	ASSERT_(L > 30 && W > 15 && alcoves >= 0);
	CSyntheticWorld w;
	constexpr double kDepth = 1.5, kAlcoveWidth = 3.0, kOpening = 12.0, kPillar = 0.3;
	// South wall with niches at seeded, non-overlapping places along x.
	std::mt19937 rng(seed);
	std::uniform_real_distribution<double> ux(4, L - 4 - kAlcoveWidth);
	std::vector<double> starts;
	while (starts.size() < static_cast<size_t>(alcoves))
	{
		const double x = ux(rng);
		if (std::all_of(starts.begin(), starts.end(),
						[&](double s) { return std::abs(s - x) > kAlcoveWidth + 1; }))
			starts.push_back(x);
	}
	std::sort(starts.begin(), starts.end());
	double x = 0;
	for (const double s : starts)
	{
		w.addSegment({x, 0}, {s, 0});
		w.addSegment({s, 0}, {s, -kDepth});
		w.addSegment({s, -kDepth}, {s + kAlcoveWidth, -kDepth});
		w.addSegment({s + kAlcoveWidth, -kDepth}, {s + kAlcoveWidth, 0});
		x = s + kAlcoveWidth;
	}
	w.addSegment({x, 0}, {L, 0});
	// West end closed, east end with an opening in its middle.
	w.addSegment({0, 0}, {0, W});
	w.addSegment({L, 0}, {L, (W - kOpening) / 2});
	w.addSegment({L, (W + kOpening) / 2}, {L, W});
	// North: glass facade between two 6 m stretches of wall.
	w.addSegment({0, W}, {6, W});
	w.addSegment({L - 6, W}, {L, W});
	// Pillars: rows at y = W/4, W/2 (offset by half a bay), 3W/4, every 10 m.
	for (int row = 1; row <= 3; ++row)
		for (double px = (row == 2 ? 10.0 : 5.0); px < L - 2; px += 10)
			w.addCircle({px, row * W / 4}, kPillar, 12);
	return w;
}

CSyntheticWorld makeAlcoveGalleryWorld(double L, double W, double pitch)
{
	ASSERT_(L > 2 * pitch && W > 2 && pitch > 2.5);
	constexpr double kWidth = 2.0, kDepth = 1.5;
	CSyntheticWorld w;
	w.addSegment({0, 0}, {0, W});
	w.addSegment({L, 0}, {L, W});
	for (const double y : {0.0, W})
	{
		const double out = y == 0 ? -kDepth : W + kDepth;  // the niche's back wall
		double x = 0;
		for (double s = pitch - kWidth / 2; s + kWidth < L - 1; s += pitch)
		{
			w.addSegment({x, y}, {s, y});
			w.addSegment({s, y}, {s, out});
			w.addSegment({s, out}, {s + kWidth, out});
			w.addSegment({s + kWidth, out}, {s + kWidth, y});
			x = s + kWidth;
		}
		w.addSegment({x, y}, {L, y});
	}
	return w;
}

namespace
{
/** Panes from a to b between solid mullions (0.1 m square) every `pitch` [m]. */
void addGlassFront(CSyntheticWorld& w, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
				   double pitch, double glassReturn)
{
	const double len = (b - a).norm();
	const Eigen::Vector2d u = (b - a) / len;
	constexpr double kHalf = 0.05;  // mullion half width [m]
	for (double s = 0; s < len - 1e-9; s += pitch)
	{
		const double e = std::min(s + pitch, len);
		w.addBox(a + s * u, kHalf, kHalf);
		w.addGlass(a + (s + kHalf) * u, a + (e - kHalf) * u, glassReturn);
	}
	w.addBox(b, kHalf, kHalf);
}
}  // namespace

CSyntheticWorld makeGlassBuildingWorld(uint32_t seed, double glassReturn)
{
	CSyntheticWorld w;
	std::mt19937 rng(seed);
	std::uniform_real_distribution<double> u(0, 1);
	// South wall with five 3 m wide, 1.5 m deep niches at seeded places.
	double x = 0;
	for (int i = 0; i < 5; ++i)
	{
		const double s = 6 + 18 * i + 9 * u(rng);
		w.addSegment({x, 0}, {s, 0});
		w.addSegment({s, 0}, {s, -1.5});
		w.addSegment({s, -1.5}, {s + 3, -1.5});
		w.addSegment({s + 3, -1.5}, {s + 3, 0});
		x = s + 3;
	}
	w.addSegment({x, 0}, {100, 0});
	w.addSegment({100, 0}, {100, 60});
	w.addSegment({100, 60}, {0, 60});
	w.addSegment({0, 60}, {0, 0});
	// Offices along the north: a glass front, partitions every 8 m, a desk in each.
	addGlassFront(w, {12, 50}, {92, 50}, 4, glassReturn);
	for (double px = 12; px <= 92; px += 8)
	{
		w.addSegment({px, 50}, {px, 60});
		if (px < 92) w.addBox({px + 2 + 4 * u(rng), 55 + 2 * u(rng)}, 0.8, 0.4, u(rng));
	}
	// The courtyard block: glass south and north, a railing east, a wall west; planters.
	addGlassFront(w, {34, 22}, {66, 22}, 4, glassReturn);
	addGlassFront(w, {66, 38}, {34, 38}, 4, glassReturn);
	w.addRailing({66, 22}, {66, 38}, 0.12, 0.05);
	w.addSegment({34, 22}, {34, 38});
	for (int i = 0; i < 4; ++i)
		w.addBox({38 + 6 * i + 3 * u(rng), 26 + 8 * u(rng)}, 0.6, 0.6, u(rng));
	w.addCircle({58, 30}, 1.0, 12);
	// West hall: a railing along the stairwell void, stairs (boxes) inside it.
	w.addRailing({10, 8}, {10, 48}, 0.12, 0.05);
	for (int i = 0; i < 3; ++i) w.addBox({4, 14 + 10 * i + 6 * u(rng)}, 1.5, 0.8);
	// Pillars: a row along the south hall, and one in each of the west and east halls.
	for (double px = 15; px < 90; px += 10) w.addBox({px + 2 * u(rng), 6}, 0.3, 0.3);
	w.addCircle({16, 30}, 0.3, 12);
	w.addCircle({72, 30 + 6 * (u(rng) - 0.5)}, 0.3, 12);
	w.addCircle({86, 28 + 6 * u(rng)}, 0.4, 12);
	return w;
}

CCrowd::CCrowd(const TBox& region, int count, uint32_t seed) : m_region(region)
{
	ASSERT_(count >= 0);
	std::mt19937 rng(seed);
	std::uniform_real_distribution<double> ux(region.min.x(), region.max.x()),
		uy(region.min.y(), region.max.y()), ua(-M_PI, M_PI), us(0.5, 1.5);
	for (int i = 0; i < count; ++i)
	{
		m_start.emplace_back(ux(rng), uy(rng));
		const double a = ua(rng), v = us(rng);
		m_velocity.emplace_back(v * std::cos(a), v * std::sin(a));
	}
}

Eigen::Vector2d CCrowd::position(size_t i, double t) const
{
	// Straight walk folded back into the region (a bounce off each edge): the coordinate
	// u = start + v t taken modulo 2 * size and mirrored in its second half.
	Eigen::Vector2d p;
	for (int d = 0; d < 2; ++d)
	{
		const double lo = m_region.min[d], size = m_region.max[d] - lo;
		double u = std::fmod(m_start[i][d] - lo + m_velocity[i][d] * t, 2 * size);
		if (u < 0) u += 2 * size;
		p[d] = lo + (u <= size ? u : 2 * size - u);
	}
	return p;
}

CSyntheticWorld CCrowd::addTo(const CSyntheticWorld& world, double t,
							  const Eigen::Vector2d& robot, double keepOut) const
{
	constexpr double kPersonRadius = 0.25;  // [m]
	CSyntheticWorld w = world;
	for (size_t i = 0; i < size(); ++i)
	{
		const Eigen::Vector2d p = position(i, t);
		if ((p - robot).norm() >= keepOut + kPersonRadius) w.addCircle(p, kPersonRadius, 8);
	}
	return w;
}

mrpt::math::TPose2D noisyIncrement(const mrpt::math::TPose2D& inc, const TOdometryNoise& n,
								   std::mt19937& rng)
{
	// Thrun's decomposition: rotate rot1, translate trans, rotate rot2.
	const double trans = std::hypot(inc.x, inc.y);
	const double rot1 = trans > 1e-9 ? std::atan2(inc.y, inc.x) : 0.0;
	const double rot2 = mrpt::math::wrapToPi(inc.phi - rot1);
	std::normal_distribution<double> N(0.0, 1.0);
	const double r1 = rot1 + N(rng) * (n.a1 * std::abs(rot1) + n.a2 * trans);
	const double t = trans + N(rng) * (n.a3 * trans + n.a4 * (std::abs(rot1) + std::abs(rot2)));
	const double r2 = rot2 + N(rng) * (n.a1 * std::abs(rot2) + n.a2 * trans);
	return {t * std::cos(r1), t * std::sin(r1), mrpt::math::wrapToPi(r1 + r2)};
}

TTrajectory makeTrajectory(const std::vector<Eigen::Vector2d>& wp, double step,
						   const TOdometryNoise& noise, uint32_t seed, double maxTurn)
{
	ASSERT_GE_(wp.size(), 2U);
	ASSERT_(step > 0 && maxTurn > 0);
	TTrajectory tr;
	auto heading = [&](size_t i)
	{ return std::atan2((wp[i + 1] - wp[i]).y(), (wp[i + 1] - wp[i]).x()); };
	mrpt::math::TPose2D cur(wp[0].x(), wp[0].y(), heading(0));
	tr.truePoses.push_back(cur);
	for (size_t i = 0; i + 1 < wp.size(); ++i)
	{
		// Turn in place towards the segment's heading.
		const double target = heading(i);
		for (double d = mrpt::math::wrapToPi(target - cur.phi); std::abs(d) > 1e-12;
			 d = mrpt::math::wrapToPi(target - cur.phi))
		{
			cur.phi = mrpt::math::wrapToPi(cur.phi + std::clamp(d, -maxTurn, maxTurn));
			tr.truePoses.push_back(cur);
		}
		// Drive along it.
		const double len = (wp[i + 1] - wp[i]).norm();
		for (double done = 0; done < len - 1e-9;)
		{
			const double ds = std::min(step, len - done);
			done += ds;
			const Eigen::Vector2d p = wp[i] + (wp[i + 1] - wp[i]) * (done / len);
			cur = mrpt::math::TPose2D(p.x(), p.y(), target);
			tr.truePoses.push_back(cur);
		}
	}
	std::mt19937 rng(seed);
	tr.odometryPoses.push_back(tr.truePoses.front());
	for (size_t k = 0; k + 1 < tr.truePoses.size(); ++k)
	{
		const auto inc =
			noisyIncrement(lrgc::between(tr.truePoses[k], tr.truePoses[k + 1]), noise, rng);
		tr.odometryIncrements.push_back(inc);
		tr.odometryPoses.push_back(lrgc::compose(tr.odometryPoses.back(), inc));
	}
	return tr;
}

}  // namespace lrgc::test
