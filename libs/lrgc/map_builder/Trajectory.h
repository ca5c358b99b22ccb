/* A trajectory: one robot pose (map <- robot) per scan, at the scan's own timestamp, in the
 * order the scans were processed (file order; timestamps may jitter backwards). */
#pragma once

#include <mrpt/core/Clock.h>
#include <mrpt/math/TPose2D.h>

#include <vector>

namespace lrgc
{
struct TStampedPose
{
	mrpt::Clock::time_point timestamp{};
	mrpt::math::TPose2D robotInMap;  //!< (map <- robot) [m, m, rad]
};
using TTrajectory = std::vector<TStampedPose>;

}  // namespace lrgc
