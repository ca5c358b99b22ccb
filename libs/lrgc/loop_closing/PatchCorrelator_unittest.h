/* Shared by CPatchCorrelator's unit tests (PatchCorrelator_unittest.cpp: the queries, their
 * filters, rivals and peaks; PatchCorrelator_corridor_unittest.cpp: doors and featureless
 * corridors, straight ridges; PatchCorrelator_search_unittest.cpp: the search core of
 * correlation_search.h): synthetic segment worlds with known poses.
 *
 * A small generator of their own (tests/support/synthetic_world models a whole laser and
 * building; these tests need only segments and exact rays): a world is a set of wall segments;
 * the old map is the walls sampled every 2 cm; a patch is the ray-cast scans (180 beams, 1 cm
 * noise) of a short robot path, expressed in the frame of the path's last pose, which is
 * therefore the true patchInMap.
 */
#pragma once

#include <lrgc/common/se2.h>
#include <mrpt/math/TPose2D.h>
#include <mrpt/math/wrap2pi.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace lrgc::test
{
using mrpt::math::TPose2D;
using Points = std::vector<Eigen::Vector2d>;

struct Segment
{
	Eigen::Vector2d a, b;
};
using World = std::vector<Segment>;

// A square room of side `size` with `n` random interior walls (0.5 to 3 m).
inline World randomWorld(std::mt19937& rng, double size, int n)
{
	World w{{{0, 0}, {size, 0}},
			{{size, 0}, {size, size}},
			{{size, size}, {0, size}},
			{{0, size}, {0, 0}}};
	std::uniform_real_distribution<double> pos(0.5, size - 0.5), len(0.5, 3.0),
		ang(-M_PI, M_PI);
	for (int k = 0; k < n; ++k)
	{
		const Eigen::Vector2d a(pos(rng), pos(rng));
		const double t = ang(rng), l = len(rng);
		w.push_back({a, a + l * Eigen::Vector2d(std::cos(t), std::sin(t))});
	}
	return w;
}

inline double angleDiff(double a, double b)
{
	return std::abs(mrpt::math::wrapToPi(a - b));
}

// One bay of a wall at y with a door: the wall from x to the door, then the door (`door` m)
// to x + period, with 0.4 m jambs at both of its sides, away from the corridor's axis y = 0.
inline void pushDoorBay(World& w, double x, double y, double period, double door)
{
	const double s = y > 0 ? 1 : -1;
	w.push_back({{x, y}, {x + period - door, y}});
	w.push_back({{x + period - door, y}, {x + period - door, y + 0.4 * s}});
	w.push_back({{x + period, y}, {x + period, y + 0.4 * s}});
}

// Corridor along x (walls at y = +-1) from -20 to 20 m; with `period` > 0, a 0.9 m door
// every `period` metres in both walls, each with 0.4 m jambs.
inline World corridor(double period)
{
	World w;
	const double x0 = -20, x1 = 20, door = 0.9;
	for (const double y : {-1.0, 1.0})
	{
		if (period <= 0)
		{
			w.push_back({{x0, y}, {x1, y}});
			continue;
		}
		for (double x = x0; x < x1; x += period) pushDoorBay(w, x, y, period, door);
	}
	return w;
}

// Doors every 3 m in a corridor (walls at y = +-1, as corridor()) from x = -20 to -5, a plain
// wall to x = -3, then a hall 5 m wide (walls at y = +-2.5) to x = 20: the doors' look-alikes
// end at x = -5.
inline World doorsThenHall()
{
	World w;
	const double door = 0.9, end = -3;
	for (const double y : {-1.0, 1.0})
	{
		const double s = y > 0 ? 1 : -1;
		double x = -20;
		for (; x + 3.0 <= end + 1e-9; x += 3.0) pushDoorBay(w, x, y, 3.0, door);
		w.push_back({{x, y}, {end, y}});
		w.push_back({{end, y}, {end, 2.5 * s}});
		w.push_back({{end, 2.5 * s}, {20, 2.5 * s}});
	}
	return w;
}

inline Points rasterise(const World& w, double spacing = 0.02)
{
	Points pts;
	for (const auto& s : w)
	{
		const int n = std::max(1, int(std::ceil((s.b - s.a).norm() / spacing)));
		for (int k = 0; k <= n; ++k) pts.push_back(s.a + (s.b - s.a) * (double(k) / n));
	}
	return pts;
}

// Scan from `robot`: nearest hit of each beam (-90..+90 deg) in the robot frame.
inline Points raycast(const World& w, const TPose2D& robot, std::mt19937& rng, double maxRange)
{
	std::normal_distribution<double> noise(0, 0.01);
	Points pts;
	const Eigen::Vector2d o(robot.x, robot.y);
	for (int k = 0; k < 180; ++k)
	{
		const double beam = -M_PI / 2 + M_PI * k / 179.0;
		const Eigen::Vector2d d(std::cos(robot.phi + beam), std::sin(robot.phi + beam));
		double best = maxRange;
		for (const auto& s : w)
		{
			const Eigen::Vector2d e = s.b - s.a, r = s.a - o;
			const double den = d.x() * e.y() - d.y() * e.x();
			if (std::abs(den) < 1e-12) continue;
			const double t = (r.x() * e.y() - r.y() * e.x()) / den;
			const double u = (r.x() * d.y() - r.y() * d.x()) / den;
			if (t > 0.05 && u >= 0 && u <= 1) best = std::min(best, t);
		}
		if (best >= maxRange) continue;
		const double r = best + noise(rng);
		pts.emplace_back(r * std::cos(beam), r * std::sin(beam));
	}
	return pts;
}

// Patch of `n` scans along a path ending at `last` (straight, 0.15 m per scan), in the
// frame of `last`.
inline Points makePatch(const World& w, const TPose2D& last, int n, std::mt19937& rng,
						double maxRange = 8.0)
{
	Points patch;
	for (int k = n - 1; k >= 0; --k)
	{
		const TPose2D robot = lrgc::compose(last, TPose2D(-0.15 * k, 0, 0.01 * k));
		const TPose2D robotInPatch = lrgc::between(last, robot);
		for (const auto& p : raycast(w, robot, rng, maxRange))
			patch.push_back(lrgc::transformPoint(robotInPatch, p));
	}
	return patch;
}

}  // namespace lrgc::test
