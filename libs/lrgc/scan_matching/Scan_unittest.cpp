/* scanFromObservation's de-skewing (Scan.h): a scan taken while the robot turns, converted
 * with the motion over its sweep, lands on the walls as seen from the middle beam's pose; and
 * without it, the scan is visibly bent. A denoised scan's match stride. */
#include <gtest/gtest.h>
#include <lrgc/scan_matching/Scan.h>

#include <algorithm>
#include <cmath>
#include <tuple>

using namespace lrgc;

namespace
{
constexpr double kHalfX = 4.0, kHalfY = 3.0;  // [m] rectangular room around the robot

/** Range from the origin along direction a [rad] to the room's walls. */
double rangeToWalls(double a)
{
	const double c = std::cos(a), s = std::sin(a);
	double r = 1e9;
	if (std::abs(c) > 1e-12) r = std::min(r, kHalfX / std::abs(c));
	if (std::abs(s) > 1e-12) r = std::min(r, kHalfY / std::abs(s));
	return r;
}

/** Distance of a point to the nearest wall [m]. */
double offWalls(const Eigen::Vector2d& p)
{
	return std::min(std::abs(std::abs(p.x()) - kHalfX), std::abs(std::abs(p.y()) - kHalfY));
}

/** A 361-beam, 180 deg scan taken while turning at w [rad/s] over a sweep of tau [s]; the
 * robot's heading at the middle beam is 0. Beam i fires at t_i = (i / 360 - 1/2) tau. */
mrpt::obs::CObservation2DRangeScan turningScan(double w, double tau)
{
	mrpt::obs::CObservation2DRangeScan obs;
	obs.aperture = M_PI;
	obs.rightToLeft = true;
	obs.maxRange = 80;
	const size_t n = 361;
	obs.resizeScan(n);
	for (size_t i = 0; i < n; ++i)
	{
		const double t = (double(i) / (n - 1) - 0.5) * tau;
		const double beam = -M_PI / 2 + M_PI * double(i) / (n - 1);
		obs.setScanRange(i, static_cast<float>(rangeToWalls(beam + w * t)));
		obs.setScanRangeValidity(i, true);
	}
	return obs;
}

double worstOffWalls(const TScan2D& scan)
{
	double worst = 0;
	for (const auto& p : scan.points) worst = std::max(worst, offWalls(p));
	return worst;
}
}  // namespace

TEST(ScanDeskew, aTurningScanLandsOnTheWallsOfTheMiddleBeamsPose)
{
	// 2 rad/s over a 26.7 ms sweep: the last beam is 3.1 deg ahead of the first.
	const double w = 2.0, tau = 0.0267;
	const auto obs = turningScan(w, tau);
	const TScan2D deskewed =
		scanFromObservation(obs, nullptr, mrpt::math::TPose2D(0, 0, w * tau));
	ASSERT_EQ(deskewed.points.size(), 361u);
	EXPECT_LT(worstOffWalls(deskewed), 1e-4);  // float ranges: ~1e-6 relative
	// Without de-skewing the beams are off by up to w tau / 2 = 0.77 deg: several cm off the
	// walls 3-5 m away (4.3 cm here).
	const TScan2D raw = scanFromObservation(obs);
	EXPECT_GT(worstOffWalls(raw), 0.03);
}

TEST(ScanDeskew, zeroMotionLeavesTheScanAsIs)
{
	const auto obs = turningScan(0.0, 0.0267);
	const TScan2D a = scanFromObservation(obs);
	const TScan2D b = scanFromObservation(obs, nullptr, mrpt::math::TPose2D(0, 0, 0));
	ASSERT_EQ(a.points.size(), b.points.size());
	for (size_t i = 0; i < a.points.size(); ++i) EXPECT_EQ(a.points[i], b.points[i]);
	EXPECT_LT(worstOffWalls(a), 1e-4);
}

// beamDirections keeps getScanAngle(i) and its cosine and sine, bit for bit, and follows a
// change of geometry (beam count, aperture, direction).
TEST(ScanBeams, beamDirectionsAreTheScansOwnBearings)
{
	for (const auto& [n, aperture, rightToLeft] :
		 {std::tuple<size_t, float, bool>{181, float(M_PI), true},
		  {361, float(M_PI), false},
		  {181, float(M_PI), true},
		  {1081, float(1.5 * M_PI), true}})
	{
		mrpt::obs::CObservation2DRangeScan obs;
		obs.aperture = aperture;
		obs.rightToLeft = rightToLeft;
		obs.resizeScanAndAssign(n, 1.0f, true);
		const TBeamDirections& beams = beamDirections(obs);
		ASSERT_EQ(beams.angle.size(), n);
		for (size_t i = 0; i < n; ++i)
		{
			const double a = obs.getScanAngle(i);
			EXPECT_EQ(beams.angle[i], a);
			EXPECT_EQ(beams.cos[i], std::cos(a));
			EXPECT_EQ(beams.sin[i], std::sin(a));
		}
	}
}

// A noisy laser's scan (0.3 m, denoised over 2h+1 = 37 rays here) is matched on every
// kMaxDenoisedMatchStride-th point, a quiet one's on all (TScan2D::matchStride).
TEST(ScanMatchStride, aDenoisedScanIsMatchedOnEveryFourthPoint)
{
	EXPECT_EQ(denoisedMatchStride(1), 1u);
	EXPECT_EQ(denoisedMatchStride(3), 1u);
	EXPECT_EQ(denoisedMatchStride(5), 2u);
	EXPECT_EQ(denoisedMatchStride(7), 3u);
	EXPECT_EQ(denoisedMatchStride(41), kMaxDenoisedMatchStride);
	const auto obs = turningScan(0, 0);
	EXPECT_EQ(scanFromObservation(obs, nullptr, {0, 0, 0}, 0.3).matchStride,
			  kMaxDenoisedMatchStride);
	EXPECT_EQ(scanFromObservation(obs, nullptr, {0, 0, 0}, 0.02).matchStride, 1u);
	EXPECT_EQ(scanFromObservation(obs).matchStride, 1u);
}
