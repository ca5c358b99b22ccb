/* Splits a CARMEN log (.clf, plain or gzip) in two halves by file lines, for tests that map
 * the first half and continue or localise with the second: header lines ('#' comments and
 * PARAM lines) go into both halves, the other lines (ODOM, FLASER, ...) are divided at the
 * middle, in file order.
 * cutCarmenLog() makes a kidnapped robot of a log: the lines stamped within [from, to) are
 * left out, so the laser jumps to where the robot was at `to`, while the odometry (ODOM
 * poses, FLASER's laser and odometry poses) is moved to go on from where it was at `from`
 * and the stamps after the cut are moved back by the cut's length: the robot is carried off
 * in an instant without its odometry noticing.
 * cutCarmenScans() makes a session of a log: the data lines from its scan `first` up to its
 * scan `end` (FLASER lines, counted from 0), every odometry pose moved by a rigid motion, as
 * a robot whose odometry started elsewhere (a second session, in its own frame). */
#pragma once

#include <cstddef>
#include <string>

namespace lrgc::test
{
struct TSplitCounts
{
	size_t headerLines = 0, firstDataLines = 0, secondDataLines = 0;
};

/** Writes the halves of `log` to `firstOut` and `secondOut` (plain text). Throws if `log`
 * cannot be read or holds no data line. */
TSplitCounts splitCarmenLog(const std::string& log, const std::string& firstOut,
							const std::string& secondOut);

/** Writes `log` (plain CARMEN text) to `out` without its data lines stamped (ipc timestamp)
 * in [from, to), as described above; returns the shift subtracted from later stamps [s].
 * Throws if the file cannot be read or written or nothing lies on both sides of the cut. */
double cutCarmenLog(const std::string& log, const std::string& out, double from, double to);

/** A rigid motion of the plane: (moved frame <- original odometry frame) [m, rad]. */
struct TOdometryMove
{
	double x = 0, y = 0, phi = 0;
};

/** Writes `log` (.clf, plain or gzip) to `out` (plain text) with the header lines and the
 * data lines from the FLASER line `first` (counted from 0) to before the FLASER line `end`
 * (past the last: to the end), the ODOM poses and FLASER's laser and odometry poses moved:
 * p' = move (+) p. Returns the number of FLASER lines written. Throws if `log` cannot be read
 * or `out` written, or no scan lies in the range. */
size_t cutCarmenScans(const std::string& log, const std::string& out, size_t first, size_t end,
					  const TOdometryMove& move);

}  // namespace lrgc::test
