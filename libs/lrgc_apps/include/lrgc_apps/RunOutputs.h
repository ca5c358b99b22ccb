/* Everything lrgc-slam writes into its output directory at the end of a run (or when the
 * run has to stop early): the maps, the trajectory, the graph, per-scan timing and
 * stats.json. Each file is written atomically. A run that mapped no scan writes stats.json
 * only: an empty trajectory and a blank grid would pass for a map. */
#pragma once

#include "lrgc_apps/RunStats.h"
#include "lrgc_apps/JsonString.h"

#include <lrgc/map_builder/CMetricMapBuilderLRGC.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/math/TPose2D.h>

#include <map>
#include <string>
#include <vector>

namespace lrgc::apps
{
struct TRunSummary
{
	std::string input;                //!< input log path
	std::string format;               //!< "rawlog" or "carmen"
	std::string status = "complete";  //!< or "input error: ...", "nothing to map: ...", ...
	std::string configIni;  //!< config.ini's text (RunConfigFile.h); empty: not written
	/** An MRPT rawlog of the input, for pf-localization.ini (MrptClientFiles.h): the input
	 * itself, a CARMEN log's --save-rawlog conversion, a live run's capture; empty: none. */
	std::string mrptRawlog;
	size_t logEntries = 0;
	size_t malformedLines = 0;                  //!< CARMEN lines skipped as malformed
	std::map<std::string, size_t> logContents;  //!< TLogReadStats::contents
	size_t warnings = 0;
	double dataDurationSeconds = 0;  //!< last minus first scan timestamp
	double wallSeconds = 0, cpuSeconds = 0, peakRssMiB = 0;
	double finalOptimizationSeconds = 0;
	TStageTimes stages;                //!< an offline run's (started: stats.json "stages")
	std::vector<double> latencyMs;     //!< per scan, in processing order
	std::vector<double> latencyStamp;  //!< the scan's timestamp [s]
	// --initial-map: the map continued, and how the log, mapped as a piece of its own from
	// its first scan, was joined to it (CPieceJoiner).
	std::string initialMap;  //!< empty: a new map
	size_t initialMapKeyframes = 0;
	bool joined = false;               //!< the piece was joined to the map
	size_t startScans = 0;             //!< scans mapped when the piece was joined (or in all)
	size_t startAttempts = 0;          //!< global correlations tried
	size_t joinsRefusedByScan = 0;     //!< of them, passed the filters but not the scan check
	double startSeconds = 0;           //!< their time on the search thread [s]
	double joinReplayWaitSeconds = 0;  //!< the mapping thread's wait for that thread [s]
	/** The frame the log's poses are stated in: "map", or the piece's own ("the log's first
	 * scan at its odometry pose (x, y, phi)"). */
	std::string frame;
	std::string lastJoinRejection;  //!< why the last correlation failed; empty if none did
	/** (map <- piece) when the piece was joined: the join's transform, before the loops
	 * closed after it adjust the piece's keyframes. */
	mrpt::math::TPose2D pieceInMap{0, 0, 0};
	double joinScore = 0, joinAmbiguity = 0;  //!< of the correlation that joined the piece
	// --merge MAP_A MAP_B: MAP_B's keyframes replayed as the piece continuing MAP_A
	// (initialMap); the join above is then (A <- B).
	std::string mergedMap;  //!< MAP_B; empty: not a merge
	size_t mergedMapKeyframes = 0;
};

class CRunClock;

/** The run's closing figures, just before writeRunOutputs(): data duration (last minus first
 * scan timestamp), warnings, wall and CPU time so far, peak RSS. */
void finishRunSummary(TRunSummary& run, const CRunClock& clock, size_t warnings);

/** Throws CSetupError, before anything is run, unless `outDir` is a directory this process
 * may write into or can be made one (its nearest existing ancestor is such a directory): an
 * existing file, /dev/null or a read-only place is found before the first scan, not after the
 * whole run. Leaves nothing behind (write access is tried with a file made and removed). */
void checkOutputDirectory(const std::string& outDir);

/** Throws CSetupError, before anything is run, unless `path` can be written as a file by
 * this process: not a directory, not an existing non-regular file (/dev/null, a FIFO: the
 * atomic write would replace it), in an existing folder this process may write into (tried,
 * as above). `option` names it in the message ("--save-rawlog"). An existing regular file
 * passes: it is replaced whole, atomically. */
void checkOutputFile(const std::string& option, const std::string& path);

/** Everything writeRunOutputs() writes, copied out of the builder at one instant, so that the
 * files can be written on another thread while mapping goes on (the live saver). Cheap to
 * take: the keyframes' observations are shared, not copied (they never change); the rest is
 * poses, links and counters. */
struct TRunOutputsSnapshot
{
	TRunSummary run;
	TMapBuilderStats stats;
	TLoopCloserStats loopStats;
	CLaserSelector lasers;                //!< the mapped laser's label and counts
	TPoseGraphOptimizerParams optimizer;  //!< the weights graph.graph is exported with
	TTrajectory trajectory;
	CPoseGraph graph;
	mrpt::maps::CSimpleMap keyframes;
	TGridKeyframes gridKeyframes;  //!< for the grid: see CIncrementalGrid
	TGridSettings gridSettings;
};

/** Takes the snapshot; on the mapping thread, or on any thread once mapping has stopped. */
TRunOutputsSnapshot snapshotRunOutputs(const CMetricMapBuilderLRGC& builder, TRunSummary run);

/** Writes every output of `s` into `outDir`, the maps from `grid` (the grid of
 * s.gridKeyframes; unused when no scan was mapped: then stats.json alone). */
void writeRunOutputs(const TRunOutputsSnapshot& s, const mrpt::maps::COccupancyGridMap2D& grid,
					 const std::string& outDir);

/** The same, from the builder itself (its grid: CMetricMapBuilderLRGC::buildOccupancyGrid). */
void writeRunOutputs(const CMetricMapBuilderLRGC& builder, const std::string& outDir,
					 const TRunSummary& run);

/** stats.json text (exposed for tests). */
std::string statsJson(const TRunOutputsSnapshot& s);
std::string statsJson(const CMetricMapBuilderLRGC& builder, const TRunSummary& run);

}  // namespace lrgc::apps
