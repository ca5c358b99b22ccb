/* lrgc-slam as a drop-in for MRPT's icp-slam command line:
 *
 *   lrgc-slam ICP-SLAM.ini [RAWLOG]
 *
 * reads what icp-slam reads from [MappingApplication]: rawlog_file (RAWLOG overrides it, as
 * in icp-slam), rawlog_offset and logOutput_dir (paths as icp-slam takes them: relative to
 * the current folder). rawlog_offset counts as icp-slam does: a log entry is mapped once the
 * serialised objects read so far, its own included, number rawlog_offset or more (an action
 * collection and its sensory frame are two objects, a lone observation one). The map is made
 * with lrgc's parameters (the defaults, or --config's); icp-slam's own settings ([ICP], the
 * metric map sections, [MappingApplication]'s other keys) have no meaning for lrgc and are
 * reported once as ignored, not refused. logOutput_dir gets lrgc's outputs and, beside them,
 * icp-slam's names: _finalmap_.simplemap    the keyframes (the same CSimpleMap as
 * map.simplemap.gz) log_estimated_path.txt  `step x y phi` [m, m, rad], one line per log entry,
 * step = the entry's index (0-based, as lrgc reads the log), the pose of the last scan mapped
 * at or before it (final, optimised poses; entries before the first mapped scan have none and
 * no line). Differences from icp-slam: the poses are the final ones, not the online estimate; a
 * leading sensory frame without an action is entry 0 (icp-slam skips it, so its steps are one
 * less); the existing files of logOutput_dir are kept (icp-slam deletes them). */
#pragma once

#include <lrgc/map_builder/Trajectory.h>

#include <string>
#include <vector>

namespace lrgc::apps
{
struct TIcpSlamRun
{
	std::string rawlog;       //!< [MappingApplication] rawlog_file, or the RAWLOG argument
	size_t rawlogOffset = 0;  //!< rawlog objects to read before mapping (as icp-slam)
	std::string outDir;       //!< [MappingApplication] logOutput_dir
	/** "[ICP]", "[MappingApplication] LOG_FREQUENCY", ...: what lrgc does not use. */
	std::vector<std::string> ignored;
};

/** True if `path` is a file whose text has a [MappingApplication] section: an icp-slam .ini. */
bool isIcpSlamIni(const std::string& path);

/** Reads the run from an icp-slam .ini; `rawlogOverride` (non-empty) replaces rawlog_file.
 * Throws CSetupError naming the file (and line) when rawlog_file or logOutput_dir is missing
 * or empty, or rawlog_offset is not a whole number >= 0. */
TIcpSlamRun readIcpSlamIni(const std::string& path, const std::string& rawlogOverride);

/** The one line reporting the ignored settings, or empty when there are none. */
std::string ignoredIcpSlamSettings(const std::string& path, const TIcpSlamRun& run);

/** log_estimated_path.txt's text: `scansAfterEntry[k]` is the number of scans mapped after
 * log entry k; entries before the first mapped scan get no line. */
std::string icpSlamEstimatedPath(const TTrajectory& trajectory,
								 const std::vector<size_t>& scansAfterEntry);

/** Writes _finalmap_.simplemap (a copy of outDir/map.simplemap.gz) and
 * log_estimated_path.txt into `outDir`, atomically. */
void writeIcpSlamOutputs(const std::string& outDir, const TTrajectory& trajectory,
						 const std::vector<size_t>& scansAfterEntry);

}  // namespace lrgc::apps
