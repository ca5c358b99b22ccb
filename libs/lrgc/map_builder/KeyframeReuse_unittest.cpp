/* CKeyframeReuse on a known map: keyframes every 0.25 m along the room world's south side,
 * scans ray-cast at the true poses. A scan that comes back near an old keyframe is anchored
 * there only after a loop link, only outside the local window, and only where its own scan
 * agrees with its registered pose. */
#include <gtest/gtest.h>
#include <lrgc/common/se2.h>
#include <lrgc/map_builder/KeyframeReuse.h>
#include <lrgc/map_builder/MapBuilderParams.h>

#include <random>

#include "synthetic_world.h"

using namespace lrgc;
using mrpt::math::TPose2D;

namespace
{
struct TKnownMap
{
	lrgc::test::CSyntheticWorld world = lrgc::test::makeRoomWorld(42);
	CPoseGraph graph;
	TKeyframes keyframes;
	std::deque<size_t> window;  //!< the last 10 keyframes
	std::mt19937 rng{3};

	TKnownMap()
	{
		for (int i = 0; i < 28; ++i)
		{
			const TPose2D truth(1.5 + 0.25 * i, 1.5, 0.0);
			graph.addNode(truth);
			TKeyframe kf;
			kf.scan = lrgc::test::simulateScan(world, truth, {}, rng);
			keyframes.push_back(std::move(kf));
		}
		for (size_t i = 18; i < 28; ++i) window.push_back(i);
	}
	TScan2D scanAt(const TPose2D& truth)
	{
		return lrgc::test::simulateScan(world, truth, {}, rng);
	}
};

const Eigen::Matrix3d kRegCov =
	Eigen::Vector3d(1e-4, 1e-4, std::pow(0.2 * M_PI / 180, 2)).asDiagonal();
}  // namespace

TEST(KeyframeReuse, anOldKeyframeIsReusedOnlyAfterALoopLinkAndWhereTheScanAgrees)
{
	TKnownMap m;
	const TLRGCParams p;
	CKeyframeReuse reuse(p.reuse, p.builder.keyframe_distance_m, p.builder.keyframe_angle,
						 p.matcher, p.loop.link_noise);
	// Back near keyframe 3 (x = 2.25), 8 cm on and turned 3 deg: covered by it.
	const TPose2D truth(2.33, 1.52, 3 * M_PI / 180);
	const TScan2D scan = m.scanAt(truth);
	const size_t anchor = 27;
	// No loop link yet: the robot's estimate is not known to agree with the map.
	EXPECT_FALSE(m.window.empty());
	EXPECT_FALSE(
		reuse.reusableKeyframe(m.graph, m.keyframes, scan, truth, kRegCov, anchor, m.window));

	reuse.noteLoopLink(27);
	const auto r =
		reuse.reusableKeyframe(m.graph, m.keyframes, scan, truth, kRegCov, anchor, m.window);
	ASSERT_TRUE(r);
	EXPECT_EQ(r->node, 3U);  // the nearest
	const TPose2D inNode = between(m.graph.pose(3), truth);
	EXPECT_LT(translationNorm(between(inNode, r->scanInNode)), 0.02);
	EXPECT_LT(std::abs(between(inNode, r->scanInNode).phi), 0.5 * M_PI / 180);

	// A registration 15 cm off the truth: the scan's own match disagrees, no reuse.
	const TPose2D off = compose(truth, TPose2D(0.0, 0.15, 0.0));
	EXPECT_FALSE(
		reuse.reusableKeyframe(m.graph, m.keyframes, scan, off, kRegCov, anchor, m.window));
	// Turned 20 deg away from every keyframe: not covered (keyframe_angle 15 deg).
	const TPose2D turned(2.25, 1.5, 20 * M_PI / 180);
	EXPECT_FALSE(reuse.reusableKeyframe(m.graph, m.keyframes, m.scanAt(turned), turned, kRegCov,
										anchor, m.window));
	// Near keyframe 24, which is in the local window: not a candidate (its neighbours
	// outside the window are more than keyframe_distance_m away).
	const TPose2D recent(1.5 + 0.25 * 24 + 0.05, 1.5, 0.0);
	EXPECT_FALSE(reuse.reusableKeyframe(m.graph, m.keyframes, m.scanAt(recent), recent, kRegCov,
										anchor, m.window));

	// trust_keyframes new keyframes later without a loop link: the trust is gone.
	for (size_t i = 0; i < p.reuse.trust_keyframes + 1; ++i)
		m.graph.addNode(TPose2D(20, 20, 0));
	EXPECT_FALSE(
		reuse.reusableKeyframe(m.graph, m.keyframes, scan, truth, kRegCov, anchor, m.window));
}
