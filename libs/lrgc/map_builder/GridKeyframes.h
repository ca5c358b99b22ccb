/* What the occupancy grid is built from (CIncrementalGrid, IncrementalGrid.h): each keyframe's
 * laser at its pose, and the grid's settings. Apart from IncrementalGrid.h so that the map
 * builder's header, which hands these out, does not include MRPT's occupancy grid.
 */
#pragma once

#include <mrpt/math/TPose2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <cstddef>
#include <vector>

namespace lrgc
{
/** A keyframe as the grid sees it: its laser at its pose (map <- robot). */
struct TGridKeyframe
{
	mrpt::math::TPose2D robotInMap;
	mrpt::obs::CObservation2DRangeScan::Ptr laser;  //!< immutable once a keyframe's
	size_t session = 0;  //!< the mapping session that took `laser` (TKeyframe::session)
};
using TGridKeyframes = std::vector<TGridKeyframe>;

struct TGridSettings
{
	double resolution = 0.05;  //!< [m] cell size
	double maxRayLength = 30;  //!< [m] rays are inserted up to this range
	/** Newest keyframes kept out of the base: the local registration window moves them. */
	size_t settleKeyframes = 12;
};

}  // namespace lrgc
