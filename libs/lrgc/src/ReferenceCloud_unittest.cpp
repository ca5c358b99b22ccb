/* CReferenceCloud: reduction, line fits against the known world, exact nearest neighbours. */
#include <gtest/gtest.h>
#include <lrgc/ReferenceCloud.h>
#include <lrgc/ScanMatcher.h>
#include <lrgc/se2.h>

#include <Eigen/Geometry>
#include <cmath>
#include <iostream>

#include "synthetic_world.h"

using namespace lrgc;
using namespace lrgc::test;
using mrpt::math::TPose2D;

namespace
{
/** Unit normal of the world segment nearest to p (world frame). */
Eigen::Vector2d nearestSegmentNormal(const CSyntheticWorld& w, const Eigen::Vector2d& p)
{
	double best = 1e9;
	Eigen::Vector2d n(0, 0);
	for (const auto& s : w.segments())
	{
		const Eigen::Vector2d e = s.b - s.a;
		const double t = std::clamp((p - s.a).dot(e) / e.squaredNorm(), 0.0, 1.0);
		const double d = (s.a + t * e - p).norm();
		if (d < best) best = d, n = Eigen::Vector2d(-e.y(), e.x()).normalized();
	}
	return n;
}
}  // namespace

TEST(ReferenceCloud, lineAnchorsLieOnTheWallsWithTheirNormals)
{
	const auto world = makeRoomWorld(3);
	std::mt19937 rng(11);
	TLaserSimParams laser;
	laser.rangeNoiseStd = 0.01;
	const TPose2D pose(5, 3.5, 0.3);
	const auto scan = simulateScan(world, pose, laser, rng);
	const TScanMatcherParams p;
	const auto ref = CReferenceCloud::fromScan(scan, p);
	ASSERT_GT(ref.size(), 100U);
	EXPECT_LE(ref.size(), scan.points.size());
	EXPECT_EQ(ref.inputPointCount(), scan.points.size());
	int lines = 0, goodNormals = 0;
	double sumOffset2 = 0;
	for (const auto& a : ref.anchors())
	{
		if (!a.isLine) continue;
		++lines;
		const Eigen::Vector2d pw = transformPoint(pose, a.pos);
		const double dist = world.distanceToNearest(pw);
		sumOffset2 += dist * dist;
		const Eigen::Vector2d nw = Eigen::Rotation2Dd(pose.phi) * a.normal;
		if (std::abs(nw.dot(nearestSegmentNormal(world, pw))) > std::cos(5 * M_PI / 180)) ++goodNormals;
	}
	std::cout << "anchors " << ref.size() << " lines " << lines << " good normals " << goodNormals
			  << " rms offset " << std::sqrt(sumOffset2 / lines) << "\n";
	// Most of a room scan is wall: line anchors, normals within 5 deg of the true ones, and
	// the line fit removes most of the 1 cm range noise.
	EXPECT_GT(lines, 0.8 * ref.size());
	EXPECT_GT(goodNormals, 0.85 * lines);
	EXPECT_LT(std::sqrt(sumOffset2 / lines), 0.006);
}

TEST(ReferenceCloud, nearestIsExactWithinTheGate)
{
	std::mt19937 rng(5);
	std::uniform_real_distribution<double> u(-3, 3);
	std::vector<Eigen::Vector2d> pts;
	for (int i = 0; i < 2000; ++i) pts.emplace_back(u(rng), u(rng));
	TScanMatcherParams p;
	p.refResolution_m = 0.001;  // no two random points share a voxel: anchors = input points
	const CReferenceCloud ref(pts, p);
	ASSERT_EQ(ref.size(), pts.size());
	for (int t = 0; t < 2000; ++t)
	{
		const Eigen::Vector2d q(1.2 * u(rng), 1.2 * u(rng));
		const double gate = 0.02 + 0.3 * (t % 7) / 6.0;
		int brute = -1;
		double bestD = gate * gate;
		for (size_t i = 0; i < ref.size(); ++i)
			if (const double d = (ref.anchors()[i].pos - q).squaredNorm(); d < bestD) bestD = d, brute = int(i);
		double d2 = -1;
		const int got = ref.nearest(q, gate, &d2);
		ASSERT_EQ(got, brute) << "query " << q.transpose() << " gate " << gate;
		if (got >= 0)
		{
			EXPECT_DOUBLE_EQ(d2, bestD);
		}
	}
	EXPECT_EQ(CReferenceCloud().nearest({0, 0}, 1.0), -1);
}

TEST(ReferenceCloud, patchFromScansReducesOverlappingPoints)
{
	const auto world = makeRoomWorld(4);
	std::mt19937 rng(2);
	TLaserSimParams laser;
	std::vector<TScan2D> scans;
	std::vector<TPose2D> poses;
	for (int k = 0; k < 10; ++k)
	{
		poses.emplace_back(3 + 0.2 * k, 3.5, 0.05 * k);
		scans.push_back(simulateScan(world, poses.back(), laser, rng));
	}
	const TScanMatcherParams p;
	const auto ref = CReferenceCloud::fromScans(scans, poses, p);
	EXPECT_GT(ref.inputPointCount(), 3000U);
	EXPECT_LT(ref.size(), 0.6 * ref.inputPointCount());  // ten views of the same walls
	// Ten scans average out: anchors lie closer to the walls than a single scan's.
	double sum2 = 0;
	int lines = 0;
	for (const auto& a : ref.anchors())
	{
		if (!a.isLine) continue;
		sum2 += std::pow(world.distanceToNearest(a.pos), 2);
		++lines;
	}
	EXPECT_LT(std::sqrt(sum2 / lines), 0.004);
	EXPECT_NEAR(std::sqrt(ref.noiseVariance()), laser.rangeNoiseStd, 0.5 * laser.rangeNoiseStd);
	EXPECT_THROW(CReferenceCloud::fromScans(scans, {}, p), std::exception);
}
