/* Test helpers for the log readers: byte-level file surgery (truncate, corrupt, reorder),
 * gzip in and out, and CARMEN line builders for logs the tests generate themselves. */
#pragma once

#include <mrpt/math/TPose2D.h>

#include <string>
#include <vector>

namespace lrgc::test
{
std::string readFileBytes(const std::string& path);
void writeFileBytes(const std::string& path, const std::string& bytes);
/** The uncompressed content of a plain or gzip file. */
std::string readUncompressed(const std::string& path);
/** Writes `bytes` gzip-compressed (as MRPT writes .rawlog and .gz files). */
void writeGzFile(const std::string& path, const std::string& bytes);

/** "%.6f"-formatted CARMEN timestamp fields "t nohost t". */
std::string carmenStamp(double t);
/** FLASER/RLASER line: n r_1..r_n laser pose, robot pose, timestamp. Ranges printed with
 * %.2f (NaN/inf as "nan"/"inf"). */
std::string flaserLine(const std::vector<double>& ranges, const mrpt::math::TPose2D& laser,
					   const mrpt::math::TPose2D& robot, double t,
					   const std::string& message = "FLASER");
std::string odomLine(const mrpt::math::TPose2D& pose, double t);
/** ROBOTLASER1 line with 2 remission values, tv = 0.1, rv = 0.2. */
std::string robotLaser1Line(double startAngle, double fov, double resolution, double maxRange,
							const std::vector<double>& ranges, const mrpt::math::TPose2D& laser,
							const mrpt::math::TPose2D& robot, double t);

}  // namespace lrgc::test
