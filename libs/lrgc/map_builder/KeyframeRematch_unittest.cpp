/* CKeyframeRematcher: the end-of-run re-match of an unmatched keyframe (KeyframeRematch.h).
 * The room world, driven along y = 3.2 facing +x (the old visit), then back along y = 3.7
 * facing -x (the new visit); one keyframe of the new visit, k, matched nothing online and
 * kept its odometry's pose, 25 deg off in heading. The old visit's keyframes and k see all
 * around (360 deg), the new visit's only the half ahead: the old visit explains more of k's
 * scan and wins the wide match, while the link is read in the frame of the nearest keyframe,
 * of the new visit. Where the map's two visits agree, the re-match turns k back to its true
 * pose; where the map holds them 0.25 m apart along the path (laps not aligned there: the
 * glass atrium's corners, doc/generalisation.md), the map is no evidence for k's pose, and k
 * stays where it is (before, k moved 0.25 m onto the old visit, linked to the new one 0.25 m
 * off the truth). */
#include <gtest/gtest.h>
#include <lrgc/common/se2.h>
#include <lrgc/map_builder/KeyframeRematch.h>
#include <lrgc/loop_closing/LoopCloserParams.h>
#include <lrgc/scan_matching/ScanMatcherParams.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/math/wrap2pi.h>

#include <cmath>
#include <random>

#include "synthetic_world.h"

using namespace lrgc;
using mrpt::math::TPose2D;

namespace
{
struct TTwoVisits
{
	test::CSyntheticWorld world = test::makeRoomWorld(5, 4);
	TKeyframes keyframes;
	CPoseGraph graph;
	std::vector<TPose2D> truth;
	size_t k = 0;  //!< the unmatched keyframe
	std::mt19937 rng{3};

	/** A keyframe at `truePose`, placed at `inMap`, chained to the previous one by odometry
	 * (the relative pose as placed: the chain holds the map as it is). */
	void add(const TPose2D& truePose, const TPose2D& inMap, double fov_deg = 360)
	{
		TKeyframe kf;
		test::TLaserSimParams laser;
		laser.fov_deg = fov_deg;
		kf.scan = test::simulateScan(world, truePose, laser, rng);
		kf.scanIndex = keyframes.size();
		keyframes.push_back(std::move(kf));
		truth.push_back(truePose);
		const size_t id = graph.addNode(inMap);
		if (id > 0)
			graph.addLink({id - 1, id, between(graph.pose(id - 1), inMap),
						   Eigen::Matrix3d::Identity() * 1e4, LinkType::Odometry});
	}

	/** The new visit placed `shift` [m] along x off the old one in the map. */
	explicit TTwoVisits(double shift)
	{
		for (int i = 0; i < 14; ++i) add({2.0 + 0.3 * i, 3.2, 0}, {2.0 + 0.3 * i, 3.2, 0});
		// The robot away from the place (beyond the re-match's 3 m): another visit follows.
		for (int i = 0; i < 5; ++i) add({8.5, 5.5 + 0.1 * i, 0}, {8.5, 5.5 + 0.1 * i, 0});
		for (int i = 0; i < 11; ++i)
		{
			const TPose2D p(5.6 - 0.3 * i, 3.7, M_PI);
			TPose2D inMap(p.x + shift, p.y, p.phi);
			if (i == 5)
			{
				k = keyframes.size();
				inMap.phi = mrpt::math::wrapToPi(inMap.phi + mrpt::DEG2RAD(25.0));
			}
			add(p, inMap, i == 5 ? 360 : 180);
		}
	}

	std::vector<TRematchedKeyframe> rematch()
	{
		const TScanMatcherParams matcher;
		const TLoopCloserParams loop;
		const CKeyframeRematcher rematcher(matcher, mrpt::DEG2RAD(45.0), 16.27,
										   Eigen::Vector3d(0.01, 0.01, 0.01).asDiagonal(),
										   loop.link_noise);
		return rematcher.rematch(graph, keyframes, {k});
	}
};
}  // namespace

TEST(KeyframeRematch, turnsTheKeyframeBackWhereTheMapsVisitsAgree)
{
	TTwoVisits run(0.0);
	const auto moved = run.rematch();
	ASSERT_EQ(moved.size(), 1U);
	EXPECT_EQ(moved[0].node, run.k);
	const TPose2D off = between(run.truth[run.k], run.graph.pose(run.k));
	EXPECT_LT(translationNorm(off), 0.05);
	EXPECT_LT(std::abs(off.phi), mrpt::DEG2RAD(1.0));
}

TEST(KeyframeRematch, leavesTheKeyframeWhereTheMapsVisitsDisagree)
{
	TTwoVisits run(0.25);
	const size_t links = run.graph.numLinks();
	const TPose2D before = run.graph.pose(run.k);
	EXPECT_TRUE(run.rematch().empty());
	EXPECT_EQ(run.graph.numLinks(), links);
	EXPECT_EQ(translationNorm(between(before, run.graph.pose(run.k))), 0.0);
}
