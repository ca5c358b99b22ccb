/* CScanMatcher::matchWide on the synthetic world: large heading errors recovered, and a right
 * guess kept in an aliased gallery. Every trial is seeded. */
#include <gtest/gtest.h>
#include <lrgc/scan_matching/ScanMatcher.h>
#include <lrgc/common/se2.h>

#include <Eigen/Dense>
#include <cmath>

#include "ScanMatcher_unittest.h"
#include "synthetic_world.h"

using namespace lrgc;
using namespace lrgc::test;
using mrpt::math::TPose2D;

TEST(ScanMatcher, matchWideRecoversLargeHeadingErrors)
{
	std::mt19937 rng(51);
	const TScanMatcherParams params;
	const CScanMatcher matcher(params);
	TLaserSimParams laser;
	std::uniform_real_distribution<double> ua(60 * kDeg, 85 * kDeg);
	int recovered = 0, wrong = 0, localOk = 0;
	const int trials = 40;
	for (int t = 0; t < trials; ++t)
	{
		const auto world = makeRoomWorld(300 + t);
		const auto [a, b] = roomPosePair(world, rng, 0.3, 10 * kDeg);
		const auto ref = CReferenceCloud::fromScan(simulateScan(world, a, laser, rng), params);
		const auto scan = simulateScan(world, b, laser, rng);
		const TPose2D truth = between(a, b);
		TPose2D guess = perturb(truth, 0.05, 0, rng);
		guess.phi = mrpt::math::wrapToPi(truth.phi + (t % 2 ? 1 : -1) * ua(rng));
		if (const auto l = matcher.match(ref, scan, guess))
			localOk += std::abs(poseError(l->scanInRef, truth).z()) < 1 * kDeg;
		const auto m = matcher.matchWide(ref, scan, guess, 90 * kDeg);
		// The starts are independent: run in any order (here last to first, as a parallel
		// run may finish them), the result is the same.
		size_t startsRun = 0;
		const auto reversed =
			matcher.matchWide(ref, scan, guess, 90 * kDeg,
							  [&](size_t n, const std::function<void(size_t)>& fn)
							  {
								  for (size_t i = n; i-- > 0;) fn(i), ++startsRun;
							  });
		EXPECT_EQ(startsRun, 25U);  // 90 deg / 7.5 deg each side, and the guess
		ASSERT_EQ(m.has_value(), reversed.has_value());
		if (m)
		{
			EXPECT_EQ(poseError(m->scanInRef, reversed->scanInRef).norm(), 0.0);
		}
		if (!m) continue;
		const Eigen::Vector3d e = poseError(m->scanInRef, truth);
		if (e.head<2>().norm() < 0.01 && std::abs(e.z()) < 0.3 * kDeg)
			++recovered;
		else
			++wrong;
	}
	std::cout << "matchWide: recovered " << recovered << "/" << trials << ", wrong " << wrong
			  << "; plain match recovered " << localOk << "\n";
	EXPECT_GE(recovered, 0.85 * trials);
	EXPECT_EQ(wrong, 0);
	EXPECT_LT(localOk, recovered);
}

// A long gallery lined with identical alcoves (issue 11: a museum hall bent by ~90 deg): a
// true 31-deg turn in place with the guess right. Scans 1 m apart make the window patch
// sparse. When the wide search runs on such a step it may keep the guess's pose or decline,
// never return an aliased one; and a real 60-85 deg heading error is still recovered there.
TEST(ScanMatcher, matchWideDoesNotOverruleARightGuessInAnAliasedGallery)
{
	const auto world = makeAlcoveGalleryWorld();
	const TScanMatcherParams params;
	const CScanMatcher matcher(params);
	TLaserSimParams laser;
	std::mt19937 rng(77);
	std::uniform_real_distribution<double> ux(12, 60), uy(3, 5), ua(60 * kDeg, 85 * kDeg);
	int wrongAtTruth = 0, keptAtTruth = 0, recovered = 0, wrongGlitch = 0;
	const int trials = 30;
	for (int t = 0; t < trials; ++t)
	{
		// Window patch: four scans 1 m apart along the axis, in the frame of the newest.
		const TPose2D newest(ux(rng), uy(rng), 0);
		std::vector<TScan2D> scans;
		std::vector<TPose2D> inNewest;
		for (int k = 3; k >= 0; --k)
		{
			const TPose2D p(newest.x - k, newest.y, 0);
			scans.push_back(simulateScan(world, p, laser, rng));
			inNewest.push_back(between(newest, p));
		}
		const auto ref = CReferenceCloud::fromScans(scans, inNewest, params);
		const double turn = (t % 2 ? 1 : -1) * 31 * kDeg;
		const TPose2D b(newest.x + 1, newest.y, turn);
		const auto scan = simulateScan(world, b, laser, rng);
		const TPose2D truth = between(newest, b);
		const TPose2D guess = perturb(truth, 0.05, 1.5 * kDeg, rng);
		if (const auto m = matcher.matchWide(ref, scan, guess, 90 * kDeg))
		{
			const Eigen::Vector3d e = poseError(m->scanInRef, truth);
			if (e.head<2>().norm() < 0.05 && std::abs(e.z()) < 0.5 * kDeg)
				++keptAtTruth;
			else
				++wrongAtTruth;
		}
		TPose2D bad = guess;
		bad.phi = mrpt::math::wrapToPi(truth.phi + (t % 2 ? -1 : 1) * ua(rng));
		if (const auto m = matcher.matchWide(ref, scan, bad, 90 * kDeg))
		{
			const Eigen::Vector3d e = poseError(m->scanInRef, truth);
			if (e.head<2>().norm() < 0.05 && std::abs(e.z()) < 0.5 * kDeg)
				++recovered;
			else
				++wrongGlitch;
		}
	}
	std::cout << "gallery matchWide, right guess: kept " << keptAtTruth << "/" << trials
			  << ", aliased " << wrongAtTruth << "; glitched guess: recovered " << recovered
			  << ", aliased " << wrongGlitch << "\n";
	EXPECT_EQ(wrongAtTruth, 0);
	EXPECT_EQ(wrongGlitch, 0);
	EXPECT_GE(keptAtTruth, trials / 2);
}
