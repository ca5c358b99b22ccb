/* Shared by CScanMatcher's unit tests on the synthetic world (ScanMatcher_unittest.cpp:
 * accuracy, consistency, corridors, outliers, rejection, a loose fit refitted;
 * ScanMatcher_wide_unittest.cpp: the wide search): pose errors, perturbed guesses and pose
 * pairs in a room world. */
#pragma once

#include <lrgc/common/se2.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <utility>

#include "synthetic_world.h"

namespace lrgc::test
{
using mrpt::math::TPose2D;

inline constexpr double kDeg = M_PI / 180;  //!< [rad]

/** est - truth: x, y [m], heading wrapped [rad]. */
inline Eigen::Vector3d poseError(const TPose2D& est, const TPose2D& truth)
{
	return {est.x - truth.x, est.y - truth.y, mrpt::math::wrapToPi(est.phi - truth.phi)};
}

inline TPose2D perturb(const TPose2D& p, double sdXY, double sdPhi, std::mt19937& rng)
{
	std::normal_distribution<double> N(0, 1);
	return {p.x + sdXY * N(rng), p.y + sdXY * N(rng),
			mrpt::math::wrapToPi(p.phi + sdPhi * N(rng))};
}

/** A pair of poses in a room world: A free, B = A (+) a random motion, also free. */
inline std::pair<TPose2D, TPose2D> roomPosePair(const CSyntheticWorld& w, std::mt19937& rng,
												double dist, double turn)
{
	const TBox region{{1, 1}, {9, 6}};
	for (;;)
	{
		const auto a = sampleFreePose(w, region, 0.5, rng);
		if (!a) continue;
		std::uniform_real_distribution<double> u(-1, 1);
		const TPose2D b = compose(*a, TPose2D(dist * u(rng), dist * u(rng), turn * u(rng)));
		if (w.distanceToNearest({b.x, b.y}) > 0.4 && b.x > 0.3 && b.x < 9.7 && b.y > 0.3 &&
			b.y < 6.7)
			return {*a, b};
	}
}
}  // namespace lrgc::test
