#include "synthetic_world.h"

#include <lrgc/common/se2.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/math/wrap2pi.h>

#include <Eigen/Geometry>
#include <algorithm>
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

std::optional<double> CSyntheticWorld::castRay(const Eigen::Vector2d& o, double angle,
											   double maxRange) const
{
	// Ray o + t d (t > 0) against segment a + s e (0 <= s <= 1):
	// t = cross(a - o, e) / cross(d, e), s = cross(a - o, d) / cross(d, e).
	const Eigen::Vector2d d(std::cos(angle), std::sin(angle));
	double best = maxRange;
	bool hit = false;
	for (const auto& seg : m_segments)
	{
		const Eigen::Vector2d e = seg.b - seg.a;
		const double den = cross2(d, e);
		if (std::abs(den) < 1e-12) continue;
		const Eigen::Vector2d w = seg.a - o;
		const double t = cross2(w, e) / den, s = cross2(w, d) / den;
		if (t > 1e-9 && t < best && s >= 0 && s <= 1) best = t, hit = true;
	}
	if (!hit) return std::nullopt;
	return best;
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
	std::normal_distribution<double> noise(0.0, laser.rangeNoiseStd);
	std::uniform_real_distribution<double> u01(0.0, 1.0);
	for (int i = 0; i < laser.beams; ++i)
	{
		const double a = -fov / 2 + fov * i / (laser.beams - 1);  // sensor frame [rad]
		const auto r0 = world.castRay(origin, sensorInWorld.phi + a, laser.maxRange);
		// Draw every random number for every beam, so that changing one rate does not
		// reshuffle the noise of the other beams.
		const double n = noise(rng), uOut = u01(rng), uOutR = u01(rng), uDrop = u01(rng);
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
