/* Timed 2D trajectories for evaluation, read from text files.
 *
 * Two formats, one pose per line, '#' starts a comment line, blank lines are skipped:
 *  - TUM:          `t x y z qx qy qz qw` (yaw taken from the unit quaternion; z, roll and
 *                  pitch are ignored), as written by lrgc-slam's trajectory.tum;
 *  - ground truth: `t x y phi` (phi in radians), as in MRPT's synthetic `*.GT.txt`.
 * A file is one or the other; the number of columns of its first pose line decides.
 *
 * Timestamps need not be monotonic: the Intel log has 631 backward jumps of its timestamps,
 * and the file order is the true order. The trajectory keeps the file order and a time-sorted
 * index beside it. A query at time t returns the pose whose timestamp equals t (within a
 * tolerance, for relations written with fewer decimals than the log), else the linear
 * interpolation between the temporally nearest poses before and after t, and nothing when t
 * lies outside the trajectory's time span.
 */
#pragma once

#include <mrpt/math/TPose2D.h>

#include <cstddef>
#include <exception>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace lrgc::apps::eval
{
/** One pose of a trajectory: the robot (or laser) in the world frame at time t [s]. */
struct TTimedPose2D
{
	double t = 0;              //!< [s]
	mrpt::math::TPose2D pose;  //!< (world <- robot), [m], [rad]
	std::size_t line = 0;  //!< line number in the source file (1-based), 0 if not from a file
};

/** How a pose at a queried time was found. */
enum class TPoseLookup
{
	Exact,        //!< a trajectory timestamp equals t within the tolerance: that pose, as is
	Interpolated  //!< between the nearest poses before and after t in time
};

struct TPoseAtTime
{
	mrpt::math::TPose2D pose;
	TPoseLookup how = TPoseLookup::Exact;
};

class CTrajectory2D
{
public:
	CTrajectory2D() = default;
	/** Takes poses in file order. Timestamps must be finite. */
	explicit CTrajectory2D(std::vector<TTimedPose2D> poses);

	/** Reads a TUM or `t x y phi` file (see the top of this header). Throws, naming file and
	 * line, on a malformed line, a non-finite number, a zero quaternion, or no pose at all. */
	static CTrajectory2D loadFromFile(const std::string& path);

	/** Parses text as if it were a file named `sourceName` (used in messages). */
	static CTrajectory2D parse(const std::string& text, const std::string& sourceName);

	/** Pose at time t [s]: a pose whose timestamp is within `exactTolerance_s` of t (the
	 * closest one; on a tie the first in file order), else interpolated linearly in x, y and
	 * along the shorter arc in phi between the nearest poses before and after t. Nothing if t
	 * is outside [earliest - tol, latest + tol]. */
	std::optional<TPoseAtTime> poseAt(double t, double exactTolerance_s = 1e-5) const;

	const std::vector<TTimedPose2D>& poses() const { return m_poses; }
	std::size_t size() const { return m_poses.size(); }
	bool empty() const { return m_poses.empty(); }
	double earliestTime() const;  //!< [s]; throws if empty
	double latestTime() const;    //!< [s]; throws if empty
	/** Number of times a timestamp is smaller than the one before it in file order. */
	std::size_t backwardTimeJumps() const;

private:
	std::vector<TTimedPose2D> m_poses;  //!< file order
	std::vector<std::size_t> m_byTime;  //!< indices into m_poses, stable-sorted by t
};

/** Yaw [rad] of a quaternion (qx, qy, qz, qw), normalised first; for a planar rotation it is
 * the rotation about z. Returns nothing for a (near) zero quaternion. */
std::optional<double> yawFromQuaternion(double qx, double qy, double qz, double qw);

/** Splits a whitespace-separated line into numbers. Throws "source:line: ..." naming the first
 * token that is not a finite number. */
std::vector<double> parseNumberLine(const std::string& line, const std::string& sourceName,
									std::size_t lineNo);

/** True for a blank line or a comment line (first non-blank character '#'). */
bool isBlankOrComment(const std::string& line);

/** Calls f(line, lineNo) for each line of `text` that is not blank or a comment. */
void forEachDataLine(const std::string& text,
					 const std::function<void(const std::string& line, std::size_t lineNo)>& f);

/** The message of an exception for a user, on one line (oneLineError, ErrorText.h). */
std::string userMessage(const std::exception& e);

/** Whole file as text; throws naming the file if it cannot be read. */
std::string readTextFile(const std::string& path);

}  // namespace lrgc::apps::eval
