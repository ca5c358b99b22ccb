/* A simulated pose graph with exact ground truth (test support: unit tests of the back-end and
 * bench/pose_graph_benchmark.cpp). */
#pragma once

#include <lrgc/pose_graph/PoseGraph.h>

#include <cstdint>
#include <vector>

namespace lrgc
{
/** A simulated pose graph with its ground truth, for tests and benchmarks. */
struct TSimulatedPoseGraph
{
	CPoseGraph graph;  //!< poses = dead reckoning from the noisy odometry links
	std::vector<mrpt::math::TPose2D> groundTruth;  //!< true (map <- robot_i)
	size_t numLoopClosures = 0;
};

/** Manhattan world in the manner of Olson's M3500: the robot drives 1 m steps on a square
 * grid of side `gridSide` cells, turning +-90 deg at random and at the border. Odometry links
 * join consecutive poses; a LoopClosure link joins the new pose to the latest earlier pose in
 * the same cell that is more than 10 poses older. Measurements = truth (+) Gaussian noise with
 * standard deviations sigmaXY [m] and sigmaPhi [rad]; information = diag of the inverse
 * variances. Deterministic for a given seed. */
TSimulatedPoseGraph simulateManhattanPoseGraph(size_t numNodes, size_t gridSide, double sigmaXY,
											   double sigmaPhi, uint32_t seed);

}  // namespace lrgc
