#include "manhattan_pose_graph.h"

#include <lrgc/common/se2.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/math/wrap2pi.h>

#include <Eigen/Core>
#include <cmath>
#include <random>
#include <unordered_map>

namespace lrgc
{
using mrpt::math::TPose2D;

TSimulatedPoseGraph simulateManhattanPoseGraph(size_t numNodes, size_t gridSide, double sigmaXY,
											   double sigmaPhi, uint32_t seed)
{
	ASSERT_(numNodes >= 1 && gridSide >= 2 && sigmaXY > 0 && sigmaPhi > 0);
	std::mt19937 rng(seed);
	std::normal_distribution<double> n01(0.0, 1.0);
	std::uniform_real_distribution<double> u01(0.0, 1.0);
	const Eigen::Matrix3d info =
		Eigen::Vector3d(1 / (sigmaXY * sigmaXY), 1 / (sigmaXY * sigmaXY),
						1 / (sigmaPhi * sigmaPhi))
			.asDiagonal();
	auto noisy = [&](const TPose2D& truth) {
		return compose(truth, {sigmaXY * n01(rng), sigmaXY * n01(rng), sigmaPhi * n01(rng)});
	};

	TSimulatedPoseGraph out;
	std::unordered_map<long, size_t> lastVisit;  // cell -> latest node there
	long cx = 0, cy = 0;
	int heading = 0;  // multiples of 90 deg
	const long side = static_cast<long>(gridSide);
	const auto cellKey = [side](long x, long y) { return x * side + y; };
	for (size_t i = 0; i < numNodes; ++i)
	{
		const TPose2D truth{double(cx), double(cy), mrpt::math::wrapToPi(heading * M_PI / 2)};
		out.groundTruth.push_back(truth);
		if (i == 0)
			out.graph.addNode(truth);
		else
		{
			const TLink odo{i - 1, i, noisy(between(out.groundTruth[i - 1], truth)), info,
							LinkType::Odometry};
			out.graph.addNode(compose(out.graph.pose(i - 1), odo.toInFrom));
			out.graph.addLink(odo);
		}
		const long key = cellKey(cx, cy);
		if (auto it = lastVisit.find(key); it != lastVisit.end() && it->second + 10 < i)
		{
			const size_t j = it->second;
			out.graph.addLink(
				{j, i, noisy(between(out.groundTruth[j], truth)), info, LinkType::LoopClosure});
			++out.numLoopClosures;
		}
		lastVisit[key] = i;
		// Next move: mostly straight, sometimes turn; never leave the grid.
		const double r = u01(rng);
		if (r < 0.15)
			heading += 1;
		else if (r < 0.30)
			heading += 3;
		for (int attempt = 0; attempt < 6; ++attempt)  // tries every direction
		{
			static const long dx[4] = {1, 0, -1, 0}, dy[4] = {0, 1, 0, -1};
			const int h = ((heading % 4) + 4) % 4;
			const long nx = cx + dx[h], ny = cy + dy[h];
			if (nx >= 0 && ny >= 0 && nx < side && ny < side)
			{
				cx = nx, cy = ny;
				break;
			}
			heading += (attempt == 0 && u01(rng) < 0.5) ? 3 : 1;
		}
		heading = ((heading % 4) + 4) % 4;
	}
	return out;
}

}  // namespace lrgc
