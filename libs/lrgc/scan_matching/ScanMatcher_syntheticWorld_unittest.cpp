/* The synthetic world used by the scan matcher tests (tests/support/synthetic_world.h):
 * ray casting, laser simulation, builders and the odometry generator. */
#include <gtest/gtest.h>
#include <lrgc/common/se2.h>

#include <cmath>

#include "synthetic_world.h"

using namespace lrgc::test;
using mrpt::math::TPose2D;

TEST(SyntheticWorld, castRayHitsTheNearestSegment)
{
	CSyntheticWorld w;
	w.addSegment({2, -1}, {2, 1});
	w.addSegment({5, -1}, {5, 1});
	ASSERT_TRUE(w.castRay({0, 0}, 0, 10));
	EXPECT_NEAR(*w.castRay({0, 0}, 0, 10), 2.0, 1e-12);
	EXPECT_NEAR(*w.castRay({3, 0}, 0, 10), 2.0, 1e-12);  // from between the walls
	EXPECT_FALSE(w.castRay({0, 0}, M_PI / 2, 10));       // nothing up there
	EXPECT_FALSE(w.castRay({0, 0}, 0, 1.5));             // beyond max range: a no-return
	EXPECT_NEAR(*w.castRay({0, 0.5}, 0, 10), 2.0, 1e-12);
	EXPECT_NEAR(w.distanceToNearest({3, 0}), 1.0, 1e-12);
}

TEST(SyntheticWorld, noiselessScanPointsLieOnTheWalls)
{
	const auto world = makeRoomWorld(9);
	std::mt19937 rng(1);
	TLaserSimParams laser;
	laser.rangeNoiseStd = 0;
	laser.sensorInRobot = TPose2D(0.2, 0.05, 0.1);  // an offset sensor
	const TPose2D robot(4, 3, 0.7);
	const auto scan = simulateScan(world, robot, laser, rng);
	ASSERT_GT(scan.points.size(), 300U);
	for (const auto& p : scan.points)
		ASSERT_LT(world.distanceToNearest(lrgc::transformPoint(robot, p)), 1e-9);
	// Drops and outliers do what they say, and the same seed gives the same scan.
	laser.dropRate = 0.5;
	std::mt19937 a(3), b(3);
	const auto s1 = simulateScan(world, robot, laser, a),
			   s2 = simulateScan(world, robot, laser, b);
	EXPECT_EQ(s1.points, s2.points);
	EXPECT_NEAR(double(s1.points.size()) / scan.points.size(), 0.5, 0.1);
	auto cut = scan;
	removeBearingSector(cut, -0.5, 0.5);
	for (const auto& p : cut.points) EXPECT_FALSE(std::abs(std::atan2(p.y(), p.x())) <= 0.5);
}

TEST(SyntheticWorld, corridorAndRepeatedRooms)
{
	const auto corridor = makeCorridorWorld(100, 2);
	EXPECT_EQ(corridor.segments().size(), 2U);
	const auto rooms = makeRepeatedRoomsWorld(3, 2, 6.0, 1.0);
	const TBox b = rooms.bounds();
	EXPECT_NEAR(b.max.x(), 18, 1e-12);
	EXPECT_NEAR(b.max.y(), 12, 1e-12);
	// Identical rooms: the same relative pose in two rooms sees the same scan.
	std::mt19937 r1(4), r2(4);
	TLaserSimParams laser;
	laser.rangeNoiseStd = 0;
	laser.maxRange = 2.5;  // stays inside one room
	const auto s1 = simulateScan(rooms, TPose2D(2, 2.5, 0.3), laser, r1);
	const auto s2 = simulateScan(rooms, TPose2D(8, 8.5, 0.3), laser, r2);
	ASSERT_EQ(s1.points.size(), s2.points.size());
	for (size_t i = 0; i < s1.points.size(); ++i)
		EXPECT_LT((s1.points[i] - s2.points[i]).norm(), 1e-9);
}

TEST(SyntheticWorld, trajectoryAndOdometry)
{
	const std::vector<Eigen::Vector2d> wp{{1, 1}, {5, 1}, {5, 4}};
	const auto tr = makeTrajectory(wp, 0.2, TOdometryNoise{}, 7);
	ASSERT_GE(tr.truePoses.size(), 36U);  // 20 + turns + 15
	EXPECT_EQ(tr.odometryIncrements.size(), tr.truePoses.size() - 1);
	EXPECT_EQ(tr.odometryPoses.size(), tr.truePoses.size());
	EXPECT_NEAR(tr.truePoses.back().x, 5, 1e-9);
	EXPECT_NEAR(tr.truePoses.back().y, 4, 1e-9);
	double maxStep = 0, maxTurn = 0;
	for (size_t k = 0; k + 1 < tr.truePoses.size(); ++k)
	{
		const auto d = lrgc::between(tr.truePoses[k], tr.truePoses[k + 1]);
		maxStep = std::max(maxStep, lrgc::translationNorm(d));
		maxTurn = std::max(maxTurn, std::abs(d.phi));
	}
	EXPECT_LE(maxStep, 0.2 + 1e-9);
	EXPECT_LE(maxTurn, 0.35 + 1e-9);
	// Odometry drifts (noise on), but stays near the truth over this short path.
	const double drift =
		lrgc::translationNorm(lrgc::between(tr.truePoses.back(), tr.odometryPoses.back()));
	EXPECT_GT(drift, 1e-4);
	EXPECT_LT(drift, 1.0);
	const auto exact = makeTrajectory(wp, 0.2, TOdometryNoise{0, 0, 0, 0}, 7);
	EXPECT_LT(lrgc::translationNorm(
				  lrgc::between(exact.truePoses.back(), exact.odometryPoses.back())),
			  1e-9);
}

namespace
{
/** Share of the scan's points nearer than r [m] from the sensor. */
double shareNearer(const lrgc::TScan2D& s, double r)
{
	size_t n = 0;
	for (const auto& p : s.points) n += p.norm() < r;
	return s.points.empty() ? 0.0 : double(n) / double(s.points.size());
}
}  // namespace

TEST(SyntheticWorld, glassReturnsItsShareOfTheBeamsAndTheFarWallTheRest)
{
	CSyntheticWorld w;
	w.addGlass({4, -20}, {4, 20}, 0.3);
	w.addSegment({12, -40}, {12, 40});
	EXPECT_NEAR(*w.castRay({0, 0}, 0, 30), 4.0, 1e-12) << "castRay stops at glass";
	EXPECT_NEAR(w.castBeam({0, 0}, 0, 30, 0.1)->range, 4.0, 1e-12);
	EXPECT_NEAR(w.castBeam({0, 0}, 0, 30, 0.5)->range, 12.0, 1e-12) << "draw above 0.3";
	TLaserSimParams laser;
	laser.fov_deg = 90;
	laser.beams = 1801;
	std::mt19937 rng(1);
	const auto scan = simulateScan(w, {0, 0, 0}, laser, rng);
	EXPECT_EQ(scan.points.size(), 1801U);
	EXPECT_NEAR(shareNearer(scan, 6), 0.3, 0.04);
	std::mt19937 same(1);
	EXPECT_EQ(simulateScan(w, {0, 0, 0}, laser, same).points, scan.points) << "seeded";
}

TEST(SyntheticWorld, railingPostsReturnSomeBeamsAndTheFarSideBetween)
{
	CSyntheticWorld w;
	w.addRailing({3, -10}, {3, 10}, 0.12, 0.04);
	w.addSegment({9, -30}, {9, 30});
	// Head on: a post at y = 0 (post k = 10000 / 12 is not whole: the first post is at -10).
	EXPECT_NEAR(*w.castRay({0, -10}, 0, 30), 3 - 0.02, 1e-9) << "the post's near side";
	EXPECT_NEAR(*w.castRay({0, -9.94}, 0, 30), 9, 1e-9) << "between two posts";
	TLaserSimParams laser;
	laser.fov_deg = 60;
	laser.beams = 601;
	laser.rangeNoiseStd = 0;
	std::mt19937 rng(1);
	const double near = shareNearer(simulateScan(w, {0, 0, 0}, laser, rng), 5);
	EXPECT_GT(near, 0.2) << "posts of 0.04 m every 0.12 m cover a third of the line";
	EXPECT_LT(near, 0.6);
}

TEST(SyntheticWorld, mixedPixelsLieBetweenTheEdgeAndTheBackground)
{
	CSyntheticWorld w;
	w.addSegment({3, 0}, {3, 5});  // an edge at bearing 0, the background 6 m behind
	w.addSegment({9, -10}, {9, 10});
	TLaserSimParams laser;
	laser.fov_deg = 20;
	laser.beams = 201;
	laser.rangeNoiseStd = 0;
	laser.mixedPixelRate = 1;
	laser.footprint_deg = 1;
	std::mt19937 rng(2);
	const auto scan = simulateScan(w, {0, 0, 0}, laser, rng);
	size_t between = 0;
	for (const auto& p : scan.points) between += p.x() > 3.05 && p.x() < 8.95;
	// Beams within half the spot (0.5 deg) of the edge: about 10 of 201.
	EXPECT_GE(between, 6U);
	EXPECT_LE(between, 12U);
}

TEST(SyntheticWorld, maxRangeDropoutsRiseWithRangeAndGrazing)
{
	CSyntheticWorld nearWall, farWall;
	nearWall.addSegment({2, -50}, {2, 50});
	farWall.addSegment({60, -500}, {60, 500});
	TLaserSimParams laser;
	laser.fov_deg = 40;
	laser.beams = 2001;
	laser.maxRange = 80;
	laser.maxRangeDropRate = 0.4;
	std::mt19937 rng(4);
	const size_t n0 = simulateScan(nearWall, {0, 0, 0}, laser, rng).points.size();
	const size_t n1 = simulateScan(farWall, {0, 0, 0}, laser, rng).points.size();
	// Drop probability 0.4 (r / 80 + 1 - cos): about 2 % at 2 m, 33 % at 60 m.
	EXPECT_GT(n0, 1900U);
	EXPECT_LT(n1, 1500U);
	EXPECT_GT(n1, 1200U);
}

TEST(SyntheticWorld, theSegmentsWithinRangeCastTheSameBeams)
{
	// A large world of solid walls, glass and railings; from anywhere in it, every beam cast
	// against the segments within its range hits what it hits against the whole world, bit
	// for bit (simulateScan casts against those only).
	const auto world = makeGlassAtriumWorld(3);
	const TBox box = world.bounds();
	std::mt19937 rng(5);
	std::uniform_real_distribution<double> u01(0.0, 1.0);
	size_t hits = 0, fewer = 0;
	for (int k = 0; k < 200; ++k)
	{
		const Eigen::Vector2d o =
			box.min + (box.max - box.min).cwiseProduct(Eigen::Vector2d(u01(rng), u01(rng)));
		const double range = 2 + 38 * u01(rng);
		const CSyntheticWorld near = world.within(o, range);
		fewer += near.segments().size() < world.segments().size();
		for (int b = 0; b < 90; ++b)
		{
			const double angle = 2 * M_PI * u01(rng), draw = u01(rng);
			const auto all = world.castBeam(o, angle, range, draw);
			const auto some = near.castBeam(o, angle, range, draw);
			ASSERT_EQ(all.has_value(), some.has_value()) << k << " " << b;
			if (!all) continue;
			++hits;
			ASSERT_EQ(all->range, some->range);
			ASSERT_EQ(all->cosIncidence, some->cosIncidence);
		}
	}
	EXPECT_GT(hits, 5000U);
	EXPECT_GT(fewer, 150U) << "the test must leave segments out";
}
