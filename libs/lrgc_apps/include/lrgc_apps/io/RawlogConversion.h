/* Conversion of any log lrgc-slam reads (CARMEN or rawlog) into an observations-only MRPT
 * rawlog, the layout MRPT's own tools (rawlog-edit, RawLogViewer, icp-slam) read.
 *
 * The observations are those of CLogReader, in file order with their recorded timestamps:
 * for CARMEN, per laser line a CObservationOdometry and a CObservation2DRangeScan, per ODOM
 * line a CObservationOdometry (unlike Debian's carmen2rawlog, which collapses the timestamps,
 * gives 180-beam scans a 90 deg aperture and drops ODOM). A layout-1 rawlog is flattened:
 * each odometry increment (CActionRobotMovement2D, mean of its pose change) is accumulated
 * into an absolute CObservationOdometry ("ODOMETRY"), then the frame's observations follow.
 */
#pragma once

#include <lrgc_apps/io/LogReaderOptions.h>

#include <cstddef>
#include <string>
#include <vector>

namespace lrgc::apps
{
struct TConversionStats
{
	size_t scans = 0;                      //!< CObservation2DRangeScan written
	size_t odometry = 0;                   //!< CObservationOdometry written
	size_t warnings = 0;                   //!< recoverable problems met (see `warningText`)
	std::vector<std::string> warningText;  //!< the reader's warnings, as takeWarnings()
	size_t observations = 0;               //!< objects written, all kinds
};

/** Writes `outRawlogPath` (gzip-compressed MRPT archive of observations, as MRPT writes
 * .rawlog files) atomically: on any error no file is left behind and a previous file of
 * that name is untouched. Throws CLogReadError for unreadable input (the output is then not
 * written), and an MRPT exception if the output cannot be written. */
TConversionStats convertToRawlog(const std::string& inPath, const std::string& outRawlogPath,
								 const TLogReaderOptions& options = {});

}  // namespace lrgc::apps
