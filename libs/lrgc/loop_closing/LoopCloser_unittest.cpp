/* CLoopCloser::keyframesWithinTravel, the path-length cap of the loop closer's patch
 * ([LoopCloser] patch_max_travel_m): keyframes 1 m apart (sparse scans) and 0.35 m apart
 * (dense logs), and turns on the spot, which add keyframes but no path. */
#include <gtest/gtest.h>
#include <lrgc/loop_closing/LoopCloser.h>
#include <lrgc/loop_closing/LoopCloserParams.h>

using namespace lrgc;
using mrpt::math::TPose2D;

namespace
{
CPoseGraph straightLine(size_t nodes, double step)
{
	CPoseGraph g;
	for (size_t i = 0; i < nodes; ++i) g.addNode(TPose2D(double(i) * step, 0, 0));
	return g;
}
}  // namespace

TEST(LoopCloserPatch, sparseKeyframesAreCappedByThePathTheyCover)
{
	// 60 keyframes 1 m apart: the newest and the 24 before it lie within 24 m of path.
	EXPECT_EQ(CLoopCloser::keyframesWithinTravel(straightLine(60, 1.0), 24.0), 25u);
	// Fewer keyframes than the cap covers: all of them.
	EXPECT_EQ(CLoopCloser::keyframesWithinTravel(straightLine(10, 1.0), 24.0), 10u);
	EXPECT_EQ(CLoopCloser::keyframesWithinTravel(straightLine(1, 1.0), 24.0), 1u);
}

TEST(LoopCloserPatch, denseKeyframesUnderTheDefaultCapKeepTheirFortyKeyframePatch)
{
	// 0.35 m apart (the benchmark logs' median spacing): 40 keyframes span 13.65 m.
	const TLoopCloserParams p;
	EXPECT_GE(CLoopCloser::keyframesWithinTravel(straightLine(200, 0.35), p.patch_max_travel_m),
			  p.old_map_exclusion_keyframes);
}

TEST(LoopCloserPatch, turningOnTheSpotAddsNoPath)
{
	CPoseGraph g = straightLine(30, 1.0);
	for (int i = 1; i <= 5; ++i) g.addNode(TPose2D(29, 0, 0.5 * i));
	// 5 turned keyframes at the same place, then 25 within 24 m along the line.
	EXPECT_EQ(CLoopCloser::keyframesWithinTravel(g, 24.0), 30u);
}
