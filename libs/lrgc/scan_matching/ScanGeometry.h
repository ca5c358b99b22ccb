/* The door every laser scan goes through before any stage uses it: its geometry checked once,
 * so that no later computation meets a NaN, an infinity or a number too large for a cell index
 * (issue 30: a 1e25 m reading overflowed CAnchorGrid's int64 cell indices; a NaN aperture or
 * sensor pose, or an aperture of 1e300 rad, put NaN points into a grid search).
 *
 * A scan is dropped (whole) when what places all its rays is unusable: fewer than 2 rays (one
 * ray has no angular step: its angle is NaN); an aperture
 * that is not finite or not in (0, 2 pi]; a sensor pose on the robot with a non-finite
 * coordinate or angle, or more than kMaxSensorOffset from the robot's origin; a maxRange that
 * is not finite and positive (0: no reading could be a return). A reading is clipped (marked
 * invalid, as MRPT marks excluded readings) when it is finite, valid and beyond kMaxRange: no
 * 2D laser measures that far, and such a point would only be a stray far from the map; a
 * larger maxRange is lowered to kMaxRange (MRPT's grid insertion traces rays that far). On
 * valid scans nothing changes: the observation itself is returned, untouched.
 */
#pragma once

#include <mrpt/obs/CObservation2DRangeScan.h>

#include <cstddef>
#include <string>

namespace lrgc
{
/** What checkScanGeometry() did with one scan. */
struct TScanGeometryCheck
{
	/** The scan to use: the observation itself, a copy with readings clipped, or null when
	 * the scan is dropped. */
	mrpt::obs::CObservation2DRangeScan::Ptr scan;
	std::string problem;  //!< why it was dropped ("aperture = nan rad"), else empty
	size_t clipped = 0;   //!< readings beyond kMaxRange marked invalid
};

/** Readings beyond this [m] are clipped (the farthest-reaching 2D lidars: a few hundred m). */
constexpr double kMaxRange = 1000.0;
/** A sensor farther than this [m] from the robot's origin is not on the robot. */
constexpr double kMaxSensorOffset = 100.0;

/** Checks `obs` (see the file comment); never throws on bad values. */
TScanGeometryCheck checkScanGeometry(const mrpt::obs::CObservation2DRangeScan::Ptr& obs);

}  // namespace lrgc
