/* Trajectories and odometry of synthetic_world.h: poses along a polyline of waypoints and
 * noisy odometry increments by Thrun's alpha model. */
#include "synthetic_world.h"

#include <lrgc/common/se2.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/math/wrap2pi.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace lrgc::test
{
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
