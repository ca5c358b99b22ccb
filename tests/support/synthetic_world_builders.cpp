/* World builders of synthetic_world.h: a furnished room, a corridor, repeated rooms, an open
 * hall, an alcove gallery, a museum, a glass building; and the crowd walking through a world.
 */
#include "synthetic_world.h"

#include <mrpt/core/exceptions.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace lrgc::test
{
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

namespace
{
/** A wall along x at height y from x0 to x1 (x0 < x1), cut by 2 m wide niches `depth` [m]
 * deep (towards +y for depth > 0, -y for depth < 0), one every `pitch` [m] from x0 + pitch / 2
 * while a whole niche fits 1 m before x1. */
void addNichedWallAlongX(CSyntheticWorld& w, double x0, double x1, double y, double depth,
						 double pitch)
{
	constexpr double kWidth = 2.0;
	double x = x0;
	for (double s = x0 + pitch / 2 - kWidth / 2; s + kWidth < x1 - 1; s += pitch)
	{
		w.addSegment({x, y}, {s, y});
		w.addSegment({s, y}, {s, y + depth});
		w.addSegment({s, y + depth}, {s + kWidth, y + depth});
		w.addSegment({s + kWidth, y + depth}, {s + kWidth, y});
		x = s + kWidth;
	}
	w.addSegment({x, y}, {x1, y});
}
}  // namespace

CSyntheticWorld makeMuseumWorld(uint32_t seed, double L, double W, double pitch)
{
	ASSERT_(L > 40 && W > 20 && pitch > 2.5);
	CSyntheticWorld w;
	constexpr double kDepth = 1.5, kBlockEnd = 12, kBlockHalf = 2;
	// Outer walls: niches set outwards into the long ones, the ends plain.
	addNichedWallAlongX(w, 0, L, 0, -kDepth, pitch);
	addNichedWallAlongX(w, 0, L, W, kDepth, pitch);
	w.addSegment({0, 0}, {0, W});
	w.addSegment({L, 0}, {L, W});
	// The central block between the two galleries, niched on both long faces, plain ends.
	const double y0 = W / 2 - kBlockHalf, y1 = W / 2 + kBlockHalf;
	addNichedWallAlongX(w, kBlockEnd, L - kBlockEnd, y0, kDepth, pitch);
	addNichedWallAlongX(w, kBlockEnd, L - kBlockEnd, y1, -kDepth, pitch);
	w.addSegment({kBlockEnd, y0}, {kBlockEnd, y1});
	w.addSegment({L - kBlockEnd, y0}, {L - kBlockEnd, y1});
	// A few plinths (0.6 m squares) at seeded places in the two end halls, 1-2.5 m from a wall.
	std::mt19937 rng(seed);
	std::uniform_real_distribution<double> u(0, 1);
	for (int i = 0; i < 6; ++i)
	{
		const double x = i % 2 == 0 ? 1 + 1.5 * u(rng) : L - 1 - 1.5 * u(rng);
		const double y = 3 + (W - 6) * u(rng);
		w.addBox({x, y}, 0.3, 0.3);
	}
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

CSyntheticWorld makeGlassAtriumWorld(uint32_t seed, const TGlassAtriumShape& sh)
{
	CSyntheticWorld w;
	std::mt19937 rng(seed);
	std::uniform_real_distribution<double> u(0, 1);
	const double L = sh.length, H = sh.width, d = sh.officeDepth, m = d + sh.hall;
	ASSERT_(L > 2 * m + 20 && H > 2 * m + 20);
	// Outer walls; a 10 m opening onto nothing in the west wall.
	const double door = 0.5 * H;
	w.addPolygon({{0, door + 5}, {0, H}, {L, H}, {L, 0}, {0, 0}, {0, door - 5}});
	// Offices south and north: glass fronts, partitions about every 8 m, a desk in each.
	const double x0 = m - 8, x1 = L - m + 8;
	const int offices = std::max(1, int(std::lround((x1 - x0) / 8)));
	for (const double front : {d, H - d})
	{
		const double back = front < H / 2 ? 0.0 : H;
		addGlassFront(w, {x0, front}, {x1, front}, 4, sh.glassReturn);
		for (int i = 0; i <= offices; ++i)
		{
			const double px = x0 + (x1 - x0) * i / offices;
			w.addSegment({px, front}, {px, back});
			if (i < offices)
				w.addBox({px + 2 + 4 * u(rng), 0.5 * (front + back) + 2 * (u(rng) - 0.5)}, 0.8,
						 0.4, u(rng));
		}
	}
	// The atrium: railed on all four sides, a column every 16 m along its edge.
	const std::vector<Eigen::Vector2d> edge{{m, m}, {L - m, m}, {L - m, H - m}, {m, H - m}};
	for (size_t i = 0; i < 4; ++i)
	{
		const Eigen::Vector2d a = edge[i], b = edge[(i + 1) % 4];
		w.addRailing(a, b, sh.postSpacing, sh.postDiameter);
		const double len = (b - a).norm();
		for (double t = 4 + 6 * u(rng); t < len - 2; t += 12 + 8 * u(rng))
			w.addBox(a + t / len * (b - a), 0.35, 0.35);
	}
	// A railed bridge across the atrium's middle (north-south, 3 m wide, seeded place).
	const double bx = 0.5 * L + 10 * (u(rng) - 0.5);
	w.addRailing({bx - 1.5, m}, {bx - 1.5, H - m}, sh.postSpacing, sh.postDiameter);
	w.addRailing({bx + 1.5, m}, {bx + 1.5, H - m}, sh.postSpacing, sh.postDiameter);
	// East: a railed stairwell void along the outer wall, stairs (boxes) in it.
	w.addRailing({L - 6, m - 4}, {L - 6, H - m + 4}, sh.postSpacing, sh.postDiameter);
	for (int i = 0; i < 3; ++i) w.addBox({L - 3, m + 6 + 12 * i + 6 * u(rng)}, 1.5, 0.8);
	// Benches and plant tubs along the halls' sides (1-2 m from a front or the railing).
	for (double x = m + 4 * u(rng); x < L - m; x += 8 + 10 * u(rng))
		for (const double y : {d + 1.2, m - 1.2, H - m + 1.2, H - d - 1.2})
			if (u(rng) < 0.5)
			{
				if (u(rng) < 0.5)
					w.addBox({x, y}, 1.0, 0.3);
				else
					w.addCircle({x, y}, 0.4, 12);
			}
	for (double y = m + 4 * u(rng); y < H - m; y += 8 + 10 * u(rng))
		if (u(rng) < 0.6) w.addBox({m - 1.2, y}, 0.3, 1.0);
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
}  // namespace lrgc::test
