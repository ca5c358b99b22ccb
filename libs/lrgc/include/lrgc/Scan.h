/* TScan2D: a 2D range scan as the LRGC stages use it.
 *
 * Only the valid returns are kept, as points in the robot (base) frame, i.e. the sensor pose
 * on the robot is already applied: p_robot = sensorInRobot (+) (r cos(a), r sin(a)).
 * No-return readings (invalid flag, NaN, r <= 0, r >= maxRange) are not obstacles and are
 * dropped here; the count of each kind is reported so callers can say what they skipped.
 */
#pragma once

#include <mrpt/core/Clock.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace lrgc
{
struct TScan2D
{
	/** Valid returns in the robot frame [m]. */
	std::vector<Eigen::Vector2d> points;
	/** Sensor range limit [m]; readings at or above it were no-returns. */
	double maxRange = 0;
	mrpt::Clock::time_point timestamp{};
};

/** Why readings of a scan were dropped. */
struct TScanConversionStats
{
	size_t total = 0;  //!< rays in the observation
	size_t invalidFlag = 0;  //!< marked invalid by the driver / reader
	size_t notFinite = 0;  //!< NaN or infinite range
	size_t nonPositive = 0;  //!< r <= 0
	size_t noReturn = 0;  //!< r >= maxRange
	size_t kept() const { return total - invalidFlag - notFinite - nonPositive - noReturn; }
};

/** Converts an MRPT laser observation; never throws on bad ranges (they are counted). */
TScan2D scanFromObservation(
	const mrpt::obs::CObservation2DRangeScan& obs, TScanConversionStats* stats = nullptr);

}  // namespace lrgc
