/* CReferenceCloud: reduction, line fits against the known world, exact nearest neighbours. */
#include <gtest/gtest.h>
#include <lrgc/scan_matching/ReferenceCloud.h>
#include <lrgc/scan_matching/ScanMatcher.h>
#include <lrgc/common/se2.h>

#include <Eigen/Geometry>
#include <cmath>
#include <iostream>
#include <random>
#include <tuple>
#include <vector>

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
		if (std::abs(nw.dot(nearestSegmentNormal(world, pw))) > std::cos(5 * M_PI / 180))
			++goodNormals;
	}
	std::cout << "anchors " << ref.size() << " lines " << lines << " good normals "
			  << goodNormals << " rms offset " << std::sqrt(sumOffset2 / lines) << "\n";
	// Most of a room scan is wall: line anchors, normals within 5 deg of the true ones, and
	// the line fit removes most of the 1 cm range noise.
	EXPECT_GT(lines, 0.8 * ref.size());
	EXPECT_GT(goodNormals, 0.85 * lines);
	EXPECT_LT(std::sqrt(sumOffset2 / lines), 0.006);
}

TEST(ReferenceCloud, fitTermsAreThoseOfAWeightedLeastSquaresLine)
{
	// delta_j(u) = sum_k (b0 + u b1) nu_k: moving every point of a LINE anchor's fit by the
	// same nu along the normal moves the line by nu at every u, so sum b0 = 1 and sum b1 = 0
	// (u is measured from the fit's weighted mean). POINT anchors have no terms.
	const auto world = makeRoomWorld(3);
	std::mt19937 rng(11);
	TLaserSimParams laser;
	laser.rangeNoiseStd = 0.01;
	const auto ref = CReferenceCloud::fromScan(
		simulateScan(world, TPose2D(5, 3.5, 0.3), laser, rng), TScanMatcherParams());
	size_t lines = 0;
	for (size_t j = 0; j < ref.size(); ++j)
	{
		double sumB0 = 0, sumB1 = 0;
		size_t terms = 0;
		bool selfIncluded = false;
		ref.forEachFitTerm(j,
						   [&](uint32_t k, float b0, float b1)
						   {
							   ASSERT_LT(k, ref.size());
							   EXPECT_GT(b0, 0.0F);
							   sumB0 += b0, sumB1 += b1, ++terms;
							   selfIncluded |= k == j;
						   });
		if (!ref.anchors()[j].isLine)
		{
			EXPECT_EQ(terms, 0U);
			continue;
		}
		++lines;
		EXPECT_GE(terms, 4U);
		EXPECT_TRUE(selfIncluded);  // the anchor's own point is in its neighbourhood
		EXPECT_NEAR(sumB0, 1.0, 1e-5);
		EXPECT_NEAR(sumB1, 0.0, 1e-3);  // [1/m]
	}
	EXPECT_GT(lines, 100U);
}

TEST(ReferenceCloud, fitTermReaderReplaysForEachFitTermExactly)
{
	// The noise model's record (fitTermReader): a fit's terms at its first reading, then at
	// every later one, are forEachFitTerm's, bit for bit and in its order; anchors read in a
	// scattered order, some of them twice in one reader.
	const auto world = makeRoomWorld(3);
	std::mt19937 rng(12);
	TLaserSimParams laser;
	laser.rangeNoiseStd = 0.01;
	const auto scan = simulateScan(world, TPose2D(4, 3, -0.4), laser, rng);
	auto ref = CReferenceCloud::fromScan(scan, TScanMatcherParams());
	ref.recordFitTerms();
	using TTerms = std::vector<std::tuple<uint32_t, float, float>>;
	auto direct = [&](size_t j)
	{
		TTerms t;
		ref.forEachFitTerm(j,
						   [&](uint32_t k, float b0, float b1) { t.emplace_back(k, b0, b1); });
		return t;
	};
	auto viaReader = [](CReferenceCloud::CFitTermReader& reader, size_t j)
	{
		TTerms t;
		reader.forEach(j, [&](uint32_t k, float b0, float b1) { t.emplace_back(k, b0, b1); });
		return t;
	};
	// A copy shares the record; a cloud that records nothing walks its fits at every reading.
	const CReferenceCloud copy = ref,
						  unrecorded = CReferenceCloud::fromScan(scan, TScanMatcherParams());
	size_t compared = 0;
	for (int pass = 0; pass < 3; ++pass)
	{
		auto reader = (pass == 0 ? ref : pass == 1 ? copy : unrecorded).fitTermReader();
		for (size_t i = 0; i < ref.size(); ++i)
		{
			const size_t j = (i * 7919 + 13) % ref.size();
			const TTerms expected = direct(j);
			ASSERT_EQ(viaReader(reader, j), expected) << "anchor " << j << ", pass " << pass;
			if (i % 3 == 0)
			{  // read again: the replay
				ASSERT_EQ(viaReader(reader, j), expected);
			}
			compared += !expected.empty();
		}
	}
	EXPECT_GT(compared, 200U);
}

TEST(ReferenceCloud, nearestIsExactWithinTheGate)
{
	std::mt19937 rng(5);
	std::uniform_real_distribution<double> u(-3, 3);
	std::vector<Eigen::Vector2d> pts;
	for (int i = 0; i < 2000; ++i) pts.emplace_back(u(rng), u(rng));
	TScanMatcherParams p;
	p.ref_resolution_m = 0.001;  // no two random points share a voxel: anchors = input points
	const CReferenceCloud ref(pts, p);
	ASSERT_EQ(ref.size(), pts.size());
	for (int t = 0; t < 2000; ++t)
	{
		const Eigen::Vector2d q(1.2 * u(rng), 1.2 * u(rng));
		const double gate = 0.02 + 0.3 * (t % 7) / 6.0;
		int brute = -1;
		double bestD = gate * gate;
		for (size_t i = 0; i < ref.size(); ++i)
			if (const double d = (ref.anchors()[i].pos - q).squaredNorm(); d < bestD)
				bestD = d, brute = int(i);
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

// The line fits handed out in blocks (here run last block first, as another thread could)
// give the same cloud bit for bit as run in order: each fit reads only the grid.
TEST(ReferenceCloud, lineFitsRunInAnyOrderGiveTheSameCloud)
{
	const auto world = makeRoomWorld(4);
	std::mt19937 rng(5);
	TLaserSimParams laser;
	std::vector<TScan2D> scans;
	std::vector<TPose2D> poses;
	for (int k = 0; k < 6; ++k)
	{
		poses.emplace_back(3 + 0.3 * k, 3.5 - 0.1 * k, 0.07 * k);
		scans.push_back(simulateScan(world, poses.back(), laser, rng));
	}
	const TScanMatcherParams p;
	size_t blocks = 0;
	const TParallelFor reversed = [&](size_t n, const std::function<void(size_t)>& fn)
	{
		blocks = n;
		for (size_t i = n; i-- > 0;) fn(i);
	};
	const auto inOrder = CReferenceCloud::fromScans(scans, poses, p);
	const auto shuffled = CReferenceCloud::fromScans(scans, poses, p, reversed);
	EXPECT_GT(blocks, 10U);  // the fits were handed out
	ASSERT_EQ(inOrder.size(), shuffled.size());
	EXPECT_EQ(inOrder.noiseVariance(), shuffled.noiseVariance());
	size_t lines = 0;
	for (size_t i = 0; i < inOrder.size(); ++i)
	{
		const auto &a = inOrder.anchors()[i], &b = shuffled.anchors()[i];
		ASSERT_EQ(a.pos, b.pos) << "anchor " << i;
		ASSERT_EQ(a.normal, b.normal) << "anchor " << i;
		ASSERT_EQ(a.isLine, b.isLine) << "anchor " << i;
		ASSERT_EQ(a.normalVar, b.normalVar) << "anchor " << i;
		ASSERT_EQ(a.samplingVar, b.samplingVar) << "anchor " << i;
		ASSERT_EQ(a.usable, b.usable) << "anchor " << i;
		lines += a.isLine;
	}
	EXPECT_GT(lines, inOrder.size() / 2);
}

TEST(ReferenceCloud, cropAroundAScanKeepsEveryAnchorTheScanCanReach)
{
	// Six scans of a room; the query is a seventh scan, the crop margin the one the loop
	// closer uses (correspondence gate + widest line fit + 0.2 m). Every anchor within the
	// gate of a query point must be the same, with the same line, in both clouds, and the
	// crop must actually drop points.
	const auto world = makeRoomWorld(7);
	std::mt19937 rng(5);
	std::vector<TScan2D> scans;
	std::vector<TPose2D> poses;
	for (int k = 0; k < 6; ++k)
		if (auto pose = sampleFreePose(world, world.bounds(), 0.5, rng))
		{
			scans.push_back(simulateScan(world, *pose, {}, rng));
			poses.push_back(*pose);
		}
	ASSERT_GE(scans.size(), 4U);
	TScanMatcherParams p;
	TLaserSimParams shortLaser;
	shortLaser.maxRange = 3.0;
	const auto queryPose = sampleFreePose(world, world.bounds(), 0.5, rng);
	ASSERT_TRUE(queryPose);
	const TScan2D query = simulateScan(world, *queryPose, shortLaser, rng);
	std::vector<Eigen::Vector2d> queryInRef;
	for (const auto& q : query.points) queryInRef.push_back(transformPoint(*queryPose, q));
	const double margin = p.max_correspondence_dist_m + 4 * p.normal_radius_m + 0.2;
	const CReferenceCloud full = CReferenceCloud::fromScans(scans, poses, p);
	const CReferenceCloud cropped =
		CReferenceCloud::fromScansNear(scans, poses, p, queryInRef, margin);
	EXPECT_LT(cropped.size(), full.size());
	size_t compared = 0;
	for (const auto& q : queryInRef)
	{
		const int a = full.nearest(q, p.max_correspondence_dist_m);
		const int b = cropped.nearest(q, p.max_correspondence_dist_m);
		ASSERT_EQ(a < 0, b < 0);
		if (a < 0) continue;
		const auto& fa = full.anchors()[size_t(a)];
		const auto& cb = cropped.anchors()[size_t(b)];
		EXPECT_NEAR((fa.pos - cb.pos).norm(), 0.0, 1e-12);
		EXPECT_NEAR((fa.normal - cb.normal).norm(), 0.0, 1e-12);
		EXPECT_EQ(fa.isLine, cb.isLine);
		++compared;
	}
	EXPECT_GT(compared, query.points.size() / 2);
}

// A pane 4 m ahead that returns 30 % of the beams (one a degree), a wall 10 m ahead behind it,
// a reference of six scans. A scan that happened to see through the pane on every beam is
// aligned right: the reference's own scans saw through most of the pane too, so it is porous
// and little violation is left (the pane's bins none of the six saw through). Where every
// reference scan saw the surface (a solid wall), a scan seeing past it still violates.
TEST(ReferenceCloud, aPorousSurfaceTheReferenceSawThroughIsNoViolation)
{
	auto world = [](int pane)  // 0: none, 1: glass, 2: solid
	{
		CSyntheticWorld w;
		if (pane == 1) w.addGlass({4, -3}, {4, 3}, 0.3);
		if (pane == 2) w.addSegment({4, -3}, {4, 3});
		w.addSegment({10, -8}, {10, 8});
		return w;
	};
	TLaserSimParams laser;
	laser.beams = 181;
	std::mt19937 rng(3);
	const TPose2D origin(0, 0, 0);
	const TScanMatcherParams p;
	const auto pastThePane = simulateScan(world(0), origin, laser, rng);
	for (const int pane : {1, 2})
	{
		const CSyntheticWorld w = world(pane);
		std::vector<TScan2D> scans;
		for (int k = 0; k < 6; ++k) scans.push_back(simulateScan(w, origin, laser, rng));
		const auto ref =
			CReferenceCloud::fromScans(scans, std::vector<TPose2D>(scans.size(), origin), p);
		const double v = ref.freeSpaceViolation(pastThePane, origin, 0.1);
		if (pane == 1)
			EXPECT_LT(v, 0.15)
				<< "the reference saw through the pane itself (0.40 counting it)";
		else
			EXPECT_GT(v, 0.2) << "a wall every reference scan saw cannot be seen through";
	}
}

// The free-space check in parts (the window's helper takes some): the same value bit for bit
// whatever order the parts run in, for alignments that violate in either direction or not.
TEST(ReferenceCloud, freeSpaceCheckInPartsIsTheSameInAnyOrder)
{
	const auto world = makeRoomWorld(4);
	std::mt19937 rng(9);
	std::vector<TScan2D> scans;
	std::vector<TPose2D> poses;
	for (int k = 0; k < 6; ++k)
	{
		poses.emplace_back(3 + 0.3 * k, 3.5 - 0.1 * k, 0.07 * k);
		scans.push_back(simulateScan(world, poses.back(), {}, rng));
	}
	const TScanMatcherParams p;
	const auto ref = CReferenceCloud::fromScans(scans, poses, p);
	const TPose2D truth(4.1, 3.0, 0.3);
	const TScan2D scan = simulateScan(world, truth, {}, rng);
	size_t parts = 0;
	const TParallelFor reversed = [&](size_t n, const std::function<void(size_t)>& fn)
	{
		parts = n;
		for (size_t i = n; i-- > 0;) fn(i);
	};
	size_t violating = 0;
	for (const TPose2D& at :
		 {truth, TPose2D(4.6, 3.0, 0.3), TPose2D(4.1, 3.0, 0.9), TPose2D(3.5, 2.6, -0.4)})
	{
		const double serial = ref.freeSpaceViolation(scan, at, 0.1);
		const double inParts = ref.freeSpaceViolation(scan, at, 0.1, reversed);
		EXPECT_EQ(serial, inParts) << at.asString();
		violating += serial > 0.05;
	}
	EXPECT_EQ(parts, 4U);      // both directions, two parts each
	EXPECT_GE(violating, 2U);  // the check was not trivially 0
	EXPECT_LT(ref.freeSpaceViolation(scan, truth, 0.1), 0.05);
}

TEST(ReferenceCloud, voxelSideFollowsTheNoiseInPowersOfTwo)
{
	// The widest res 2^k not above sigma, nor above maxCell; res when the noise is below 2 res.
	EXPECT_DOUBLE_EQ(CReferenceCloud::cellForNoise(0.02, 0.0, 0.075), 0.02);
	EXPECT_DOUBLE_EQ(CReferenceCloud::cellForNoise(0.02, 0.039, 0.075), 0.02);
	EXPECT_DOUBLE_EQ(CReferenceCloud::cellForNoise(0.02, 0.04, 0.075), 0.04);
	EXPECT_DOUBLE_EQ(CReferenceCloud::cellForNoise(0.02, 0.079, 0.075), 0.04);
	EXPECT_DOUBLE_EQ(CReferenceCloud::cellForNoise(0.02, 0.5, 0.075), 0.04);  // maxCell
	EXPECT_DOUBLE_EQ(CReferenceCloud::cellForNoise(0.02, 0.5, 0.2), 0.16);
	EXPECT_DOUBLE_EQ(CReferenceCloud::cellForNoise(0.02, 0.5, 0.01), 0.02);  // never below res
}

/* The far fit (TScanMatcherParams::far_fit_angle): one scan of a 1-degree laser samples a wall
 * 60 m away every 1.05 m, so no return has 3 neighbours within 4 normal_radius_m (0.6 m): all
 * are isolated, never matched. Fitted again within 3 deg x 60 m = 3.1 m, they are LINE anchors
 * on the wall, with its normal. */
TEST(ReferenceCloud, aFarWallOfOneScanIsLinesOnlyWithTheFarFit)
{
	TScan2D scan;
	scan.maxRange = 80;
	std::mt19937 rng(5);
	std::normal_distribution<double> noise(0, 0.01);
	for (int deg = -20; deg <= 20; ++deg)
	{
		const double th = deg * M_PI / 180, range = 60 / std::cos(th) + noise(rng);
		scan.points.emplace_back(range * std::cos(th), range * std::sin(th));
	}
	TScanMatcherParams p;
	const CReferenceCloud without = CReferenceCloud::fromScan(scan, p);
	for (const auto& a : without.anchors()) EXPECT_FALSE(a.isLine || a.usable);

	p.far_fit_angle = mrpt::DEG2RAD(3.0);
	const CReferenceCloud with = CReferenceCloud::fromScan(scan, p);
	size_t lines = 0;
	for (const auto& a : with.anchors())
		if (a.isLine)
		{
			++lines;
			EXPECT_GT(std::abs(a.normal.x()), 0.999) << "at y = " << a.pos.y();
			EXPECT_NEAR(a.pos.x(), 60, 0.05);
			EXPECT_NEAR(a.fitRadius, a.pos.norm() * mrpt::DEG2RAD(3.0), 0.01);  // 3.1-3.4 m
		}
	// All but the two end returns (two neighbours within R, on one side: a line needs 4
	// points).
	EXPECT_EQ(lines + 2, with.size()) << "every inner return of the wall is a line";
}
