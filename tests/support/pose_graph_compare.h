/* Comparisons of pose graphs for the back-end tests. */
#pragma once

#include <lrgc/pose_graph/PoseGraph.h>
#include <mrpt/math/wrap2pi.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace lrgc::test
{
/** RMS of the position error of every node against ground truth [m]. */
inline double rmsPositionError(const CPoseGraph& g,
							   const std::vector<mrpt::math::TPose2D>& truth)
{
	double s = 0;
	for (size_t i = 0; i < g.numNodes(); ++i)
		s += std::pow(g.pose(i).x - truth[i].x, 2) + std::pow(g.pose(i).y - truth[i].y, 2);
	return std::sqrt(s / double(g.numNodes()));
}

/** Largest difference of any coordinate of any node between two graphs [m or rad]. */
inline double maxPoseDifference(const CPoseGraph& a, const CPoseGraph& b)
{
	double m = 0;
	for (size_t i = 0; i < a.numNodes(); ++i)
		m = std::max({m, std::abs(a.pose(i).x - b.pose(i).x),
					  std::abs(a.pose(i).y - b.pose(i).y),
					  std::abs(mrpt::math::wrapToPi(a.pose(i).phi - b.pose(i).phi))});
	return m;
}
}  // namespace lrgc::test
