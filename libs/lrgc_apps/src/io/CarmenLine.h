/* Parser of one line of a CARMEN log (carmen/src/logger formats), without interpretation:
 * the values as recorded, in the odometry frame, metres, radians and seconds.
 *
 *   ODOM x y theta tv rv accel timestamp [hostname logger_timestamp]
 *   FLASER n r_1 .. r_n x y theta odom_x odom_y odom_theta timestamp [hostname logger_ts]
 *   RLASER (as FLASER, the rear laser)
 *   ROBOTLASER1 laser_type start_angle field_of_view angular_resolution maximum_range
 *     accuracy remission_mode n r_1 .. r_n m rem_1 .. rem_m x y theta odom_x odom_y
 *     odom_theta tv rv forward_safety_dist side_safety_dist turn_axis timestamp [host lts]
 *
 * (x y theta: the laser pose; odom_*: the robot pose; timestamp: ipc_timestamp.) Any other
 * first word (PARAM, SYNC, TRUEPOS...), comments (#) and blank lines are Ignored. A line
 * with a wrong field count, a field that is not a number, or a non-finite pose or timestamp
 * is Malformed, with the problem stated. Ranges are kept as written, NaN and negative ones
 * included: judging them is the reader's job. Numbers are parsed locale-independently.
 */
#pragma once

#include <mrpt/math/TPose2D.h>

#include <string>
#include <string_view>
#include <vector>

namespace lrgc::apps
{
struct TCarmenLaser
{
	std::vector<double> ranges;     //!< [m], as recorded
	mrpt::math::TPose2D laserPose;  //!< laser in the odometry frame [m, rad]
	mrpt::math::TPose2D robotPose;  //!< robot in the odometry frame [m, rad]
	double timestamp = 0;           //!< ipc_timestamp [s]
	/** ROBOTLASER1 only (else false): the fields below come from the line. */
	bool hasOwnGeometry = false;
	double startAngle = 0;         //!< first beam in the laser frame [rad]
	double angularResolution = 0;  //!< step between beams, counter-clockwise [rad]
	double maxRange = 0;           //!< [m]
	double tv = 0, rv = 0;         //!< robot velocities [m/s], [rad/s]
};

struct TCarmenOdometry
{
	mrpt::math::TPose2D pose;          //!< robot in the odometry frame [m, rad]
	double tv = 0, rv = 0, accel = 0;  //!< [m/s], [rad/s], [m/s^2]
	double timestamp = 0;              //!< ipc_timestamp [s]
};

struct TCarmenRecord
{
	enum class Kind
	{
		Ignored,
		FrontLaser,  //!< FLASER -> laser
		RearLaser,   //!< RLASER -> laser
		RobotLaser,  //!< ROBOTLASER1 -> laser
		Odometry,    //!< ODOM -> odometry
		Malformed    //!< see problem
	};
	Kind kind = Kind::Ignored;
	std::string message;  //!< first word, empty for blank and comment lines
	std::string problem;  //!< for Malformed: what is wrong, naming the field
	/** Fields after the timestamp (hostname, logger_timestamp): 0 to 2. A line cut short
	 * inside its timestamp still parses, so a line of unknown completeness (the last one,
	 * without an end of line) is trusted only if this is > 0. */
	size_t fieldsAfterTimestamp = 0;
	TCarmenLaser laser;
	TCarmenOdometry odometry;
	std::vector<std::string_view> tokens;  //!< scratch space, reused between lines
};

/** Parses `line` into `out` (reused so that its vectors keep their capacity). */
void parseCarmenLine(std::string_view line, TCarmenRecord& out);

}  // namespace lrgc::apps
