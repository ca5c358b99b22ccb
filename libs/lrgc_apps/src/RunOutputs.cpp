/* The run's output files (RunOutputs.h): the checks made before a run starts, the snapshot,
 * and the writers by kind (the snapshot's files, the grid's, the measured ones last).
 * stats.json's text is made in StatsJson.cpp. */
#include "lrgc_apps/RunOutputs.h"

#include "CommandLine.h"
#include "lrgc_apps/MapExport.h"
#include "MrptClientFiles.h"
#include "lrgc_apps/RunStats.h"
#include "lrgc_apps/SavedMap.h"
#include "Scene3D.h"
#include "atomic_file.h"

#include <lrgc/pose_graph/GraphExport.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimpleMap.h>

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>

namespace lrgc::apps
{
namespace
{
std::string timingCsv(const TRunSummary& run)
{
	std::string out = "scan_index,timestamp,latency_ms\n";
	char line[96];
	for (size_t i = 0; i < run.latencyMs.size(); ++i)
	{
		std::snprintf(line, sizeof(line), "%zu,%.6f,%.4f\n", i, run.latencyStamp[i],
					  run.latencyMs[i]);
		out += line;
	}
	return out;
}
}  // namespace

TRunOutputsSnapshot snapshotRunOutputs(const CMetricMapBuilderLRGC& builder, TRunSummary run)
{
	TRunOutputsSnapshot s;
	s.run = std::move(run);
	s.stats = builder.statsCopy();
	s.loopStats = builder.loopCloserStats();
	s.lasers = builder.lasers();
	s.optimizer = builder.params().optimizer;
	if (s.stats.scans == 0) return s;  // stats.json alone
	s.trajectory = builder.trajectory();
	s.graph = builder.graph();
	builder.getCurrentlyBuiltMap(s.keyframes);
	s.gridKeyframes = builder.gridKeyframes();
	s.gridSettings = builder.gridSettings();
	return s;
}

void checkOutputDirectory(const std::string& outDir)
{
	namespace fs = std::filesystem;
	std::error_code ec;
	const fs::path target = fs::absolute(outDir, ec);
	// The directory itself, or the nearest existing ancestor it would be created in.
	fs::path dir = target;
	while (!fs::exists(dir, ec) && dir.has_relative_path()) dir = dir.parent_path();
	const std::string option = "--out '" + outDir + "'";
	if (!fs::is_directory(dir, ec))
		throw CSetupError((dir == target
							   ? option + " is not a directory"
							   : option + ": '" + dir.string() + "' is not a directory") +
						  "; name a directory for the outputs");
	// Tried, not asked: access(W_OK) says yes to root in places no one can write (/proc).
	std::string probe = (dir / ".lrgc-write-probe-XXXXXX").string();
	const int fd = ::mkstemp(probe.data());
	if (fd < 0)
		throw CSetupError(option + ": cannot write into " +
						  (dir == target ? "it" : "'" + dir.string() + "'") + " (" +
						  std::strerror(errno) + "); name a directory you may write into");
	::close(fd);
	::unlink(probe.c_str());
}

void checkOutputFile(const std::string& option, const std::string& path)
{
	namespace fs = std::filesystem;
	std::error_code ec;
	const std::string named = option + " '" + path + "'";
	if (fs::is_directory(path, ec))
		throw CSetupError(named + " is a directory; name a file in it, e.g. '" +
						  (fs::path(path) / "log.rawlog").string() + "'");
	if (fs::exists(path, ec) && !fs::is_regular_file(path, ec))
		throw CSetupError(named + " exists and is not a regular file; name a file");
	const fs::path folder = fs::path(path).parent_path();
	const fs::path dir = folder.empty() ? fs::path(".") : folder;
	if (!fs::is_directory(dir, ec))
		throw CSetupError(named + ": '" + dir.string() +
						  "' is not a directory; create it first, or name another file");
	std::string probe = (dir / ".lrgc-write-probe-XXXXXX").string();
	const int fd = ::mkstemp(probe.data());
	if (fd < 0)
		throw CSetupError(named + ": cannot write into '" + dir.string() + "' (" +
						  std::strerror(errno) +
						  "); name a file in a folder you may write into");
	::close(fd);
	::unlink(probe.c_str());
}

void finishRunSummary(TRunSummary& run, const CRunClock& clock, size_t warnings)
{
	if (!run.latencyStamp.empty())
	{
		const auto [lo, hi] =
			std::minmax_element(run.latencyStamp.begin(), run.latencyStamp.end());
		run.dataDurationSeconds = *hi - *lo;
	}
	run.warnings = warnings;
	run.wallSeconds = clock.wallSeconds();
	run.cpuSeconds = clock.cpuSeconds();
	run.peakRssMiB = CRunClock::peakRssMiB();
}

namespace
{
std::string outputPath(const std::string& outDir, const char* name)
{
	return (std::filesystem::path(outDir) / name).string();
}

// The outputs made from the snapshot alone (trajectory, graphs, keyframes, the MRPT programs'
// .ini files).
void writeSnapshotOutputs(const TRunOutputsSnapshot& s, const std::string& outDir)
{
	const auto path = [&](const char* name) { return outputPath(outDir, name); };
	writeTrajectoryTum(s.trajectory, path("trajectory.tum"));
	// One edge per node pair with the weights of our final optimisation, so that MRPT's
	// graph-slam (which keeps one edge per pair) finds our poses (GraphExport.h).
	writeGraph(toMrptLeastSquares(s.graph, s.optimizer), path("graph.graph"));
	// The whole graph (link types, disabled links), for --initial-map: SavedMap.h.
	std::vector<size_t> sessions;
	for (const auto& k : s.gridKeyframes) sessions.push_back(k.session);
	writeTextFileAtomically(path(kPoseGraphFile),
							poseGraphToText(s.graph, s.lasers.label(), sessions));
	writeSimplemap(s.keyframes, path("map.simplemap.gz"));
	writeMrptClientFiles(s, outDir);  // pf-localization.ini, observations2map.ini
}

// The outputs drawn from the occupancy grid.
void writeGridOutputs(const TRunOutputsSnapshot& s, const mrpt::maps::COccupancyGridMap2D& grid,
					  const std::string& outDir)
{
	const auto path = [&](const char* name) { return outputPath(outDir, name); };
	writeGridmap(grid, path("map.gridmap.gz"));
	writeGridPng(grid, path("map.png"));
	writeRosMap(grid, path("map"));
	writeScene3D(grid, s.trajectory, s.graph, path("map.3Dscene"));  // for SceneViewer3D
}

// config.ini, then (a run that mapped scans) the files of the snapshot and of the grid, the
// grid made by `grid`; the measured files last: timing.csv, then stats.json (a run that
// mapped no scan: stats.json alone).
void writeAll(TRunOutputsSnapshot& s, const std::string& outDir,
			  const std::function<const mrpt::maps::COccupancyGridMap2D&()>& grid)
{
	std::filesystem::create_directories(outDir);
	if (!s.run.configIni.empty())
		writeTextFileAtomically(outputPath(outDir, "config.ini"), s.run.configIni);
	if (s.stats.scans > 0)
	{
		writeSnapshotOutputs(s, outDir);
		writeGridOutputs(s, grid(), outDir);
		writeTextFileAtomically(outputPath(outDir, "timing.csv"), timingCsv(s.run));
	}
	if (s.run.stages.started()) s.run.stages.outputs = s.run.stages.lap();
	writeTextFileAtomically(outputPath(outDir, "stats.json"), statsJson(s));
}
}  // namespace

void writeRunOutputs(const TRunOutputsSnapshot& s, const mrpt::maps::COccupancyGridMap2D& grid,
					 const std::string& outDir)
{
	TRunOutputsSnapshot copy = s;  // stats.json gets the outputs' time
	writeAll(copy, outDir, [&]() -> const mrpt::maps::COccupancyGridMap2D& { return grid; });
}

void writeRunOutputs(const CMetricMapBuilderLRGC& builder, const std::string& outDir,
					 const TRunSummary& run)
{
	TRunOutputsSnapshot s = snapshotRunOutputs(builder, run);
	mrpt::maps::COccupancyGridMap2D::Ptr grid;
	writeAll(s, outDir,
			 [&]() -> const mrpt::maps::COccupancyGridMap2D&
			 {
				 grid = builder.buildOccupancyGrid();
				 return *grid;
			 });
}

}  // namespace lrgc::apps
