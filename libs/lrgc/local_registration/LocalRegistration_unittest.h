/* Shared by the unit tests of CLocalRegistration (LocalRegistration_unittest.cpp: the window
 * solve and its keyframes; LocalRegistration_registerScan_unittest.cpp: a scan's pose from its
 * prior, the wide search and its second opinions): the stage's parameters, tolerances and a
 * known run in the synthetic room world. Not installed. */
#pragma once

#include <lrgc/local_registration/LocalRegistration.h>
#include <lrgc/pose_graph/PoseGraphOptimizerParams.h>
#include <lrgc/scan_matching/ScanMatcherParams.h>
#include <lrgc/common/se2.h>

#include <cmath>
#include <random>

#include "synthetic_world.h"

namespace lrgc::test
{
/** The stage's own parameters at their defaults (those of a default [LocalRegistration],
 * [ScanMatcher] and [PoseGraphOptimizer] section), without the map builder's TLRGCParams. */
struct TStageParams
{
	TLocalRegistrationParams local;
	TScanMatcherParams matcher;
	TPoseGraphOptimizerParams optimizer;
};

constexpr double kTolXY = 0.03;               // [m]
constexpr double kTolPhi = 0.5 * M_PI / 180;  // [rad]

inline double positionError(const TPose2D& a, const TPose2D& b)
{
	return translationNorm(between(a, b));
}
inline double headingError(const TPose2D& a, const TPose2D& b)
{
	return std::abs(between(a, b).phi);
}

/** Keyframes every 0.3 m along a loop in the room world, scans ray-cast at the true poses,
 * odometry increments with about 5 cm / 3 deg of noise per step. */
struct TKnownRun
{
	CSyntheticWorld world = lrgc::test::makeRoomWorld(5, 4);
	lrgc::test::TTrajectory tr;
	TKeyframes keyframes;

	TKnownRun()
	{
		lrgc::test::TOdometryNoise noise;
		noise.a1 = 0.15, noise.a2 = 0.15, noise.a3 = 0.15, noise.a4 = 0.05;
		tr = lrgc::test::makeTrajectory(
			{{1.5, 3.5}, {5.5, 3.5}, {5.5, 5.8}, {1.2, 5.8}, {1.2, 3.0}, {4.5, 3.0}}, 0.3,
			noise, 21);
		std::mt19937 rng(4);
		for (size_t k = 0; k < tr.truePoses.size(); ++k)
		{
			TKeyframe kf;
			kf.scan = lrgc::test::simulateScan(world, tr.truePoses[k], {}, rng);
			kf.scanIndex = k;
			keyframes.push_back(std::move(kf));
		}
	}
};
}  // namespace lrgc::test
