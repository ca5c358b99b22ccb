/* CSlamApp::runOffline: the log-to-maps loop of lrgc-slam. */
#include "AppConfig.h"
#include "ErrorText.h"
#include "IcpSlamIni.h"
#include "Progress.h"
#include "RunConfigFile.h"
#include "lrgc_apps/RunOutputs.h"
#include "lrgc_apps/RunStats.h"
#include "lrgc_apps/SavedMap.h"
#include "SlamApp.h"
#include "StopSignalWatcher.h"
#include "lrgc_apps/io/LogReader.h"

#include <lrgc/common/CpuTime.h>
#include <lrgc/map_builder/CMetricMapBuilderLRGC.h>
#include <mrpt/obs/CActionCollection.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <map>

namespace lrgc::apps
{
namespace
{
constexpr size_t kMaxWarningsShown = 30;

// "1200 CObservationBearingRange, 1199 CActionRobotMovement2D": the largest counts first.
std::string describeContents(const std::map<std::string, size_t>& contents)
{
	std::vector<std::pair<std::string, size_t>> byCount(contents.begin(), contents.end());
	std::stable_sort(byCount.begin(), byCount.end(),
					 [](const auto& a, const auto& b) { return a.second > b.second; });
	std::string out;
	for (const auto& [name, n] : byCount)
		out += (out.empty() ? "" : ", ") + std::to_string(n) + " " + name;
	return out.empty() ? "no observation" : out;
}

// Why a log read to its end gave no scan to map: the status of stats.json.
std::string nothingToMap(const CLogReader& reader, const CMetricMapBuilderLRGC& builder)
{
	const TLogReadStats& r = reader.stats();
	const std::string file = "'" + reader.path() + "'";
	if (r.scans == 0 && r.emptyScans == 0)
		return "nothing to map: " + file +
			   " holds no 2D laser scan (CObservation2DRangeScan); it holds " +
			   describeContents(r.contents);
	if (const auto& lasers = builder.lasers();
		lasers.chosen() && !lasers.ignoredScans().empty())
	{
		std::string others;
		for (const auto& [label, n] : lasers.ignoredScans())
			others += (others.empty() ? "" : ", ") + label +
					  mrpt::format(" (%zu scan%s)", n, n == 1 ? "" : "s");
		return "nothing to map: " + file + " has no scan of laser '" + lasers.label() +
			   "' (--laser, [MapBuilder] laser_label); its lasers: " + others;
	}
	std::vector<std::string> why;
	if (r.emptyScans > 0)
		why.push_back(mrpt::format("%zu with under 2 readings", r.emptyScans));
	if (const size_t n = builder.lasers().badGeometryScans(); n > 0)
		why.push_back(mrpt::format("%zu dropped for their geometry: %s", n,
								   builder.lasers().firstGeometryProblem().c_str()));
	if (const size_t n = builder.stats().skippedScans; n > 0)
		why.push_back(
			mrpt::format("%zu with fewer valid returns than [MapBuilder] min_scan_points = %zu",
						 n, builder.params().builder.min_scan_points));
	std::string reasons;
	for (const auto& w : why) reasons += (reasons.empty() ? " (" : ", ") + w;
	return mrpt::format(
		"nothing to map: none of the %zu 2D laser scans of %s could be mapped%s",
		r.scans + r.emptyScans, file.c_str(), reasons.empty() ? "" : (reasons + ")").c_str());
}
// The mapping stage's figures (stats.json "stages"): its process CPU and wall, the mapping
// thread's CPU since `threadCpu0`, and from the builder, the CPU of its placement of scans and
// of the loop-closing worker thread so far.
void endMappingStage(TRunSummary& run, const CMetricMapBuilderLRGC& builder, double threadCpu0)
{
	run.stages.mapping = run.stages.lap();
	run.stages.mappingThreadCpu = threadCpuSeconds() - threadCpu0;
	run.stages.placementCpu = builder.stats().placementCpuSeconds;
	run.stages.loopWorkerCpu = builder.loopCloserStats().workerThreadCpuSeconds;
}

}  // namespace

void CSlamApp::reportWarnings(const std::vector<std::string>& warnings)
{
	for (const auto& w : warnings)
	{
		++m_warningsTotal;
		if (m_warningsShown++ < kMaxWarningsShown)
			report("warning: " + w);
		else if (m_warningsShown == kMaxWarningsShown + 1)
			report("warning: further warnings are counted in stats.json, not shown");
	}
}

int CSlamApp::runOffline(const TSlamCommandLine& cl)
{
	const TAppConfig cfg = loadAppConfig(cl);
	for (const auto& w : cfg.warnings) report("warning: " + w);  // old key names, all shown
	// Before the reader's guard process and the optimiser's threads, which inherit its mask.
	const CStopSignalWatcher signals;
	std::unique_ptr<CLogReader> reader;
	try
	{
		reader = openLog(cl.input, cfg.reader);
	}
	catch (const std::exception& e)
	{
		reportError(e);
		return kExitInputError;
	}

	CMetricMapBuilderLRGC builder(cfg.lrgc);
	builder.logging_enable_console_output = false;  // warnings are reported below
	builder.setStopToken(signals.token());  // the first signal cuts short what is in hand
	std::optional<TSavedMap> initialMap;
	if (!cl.initialMap.empty()) try
		{
			initialMap = loadSavedMap(cl.initialMap, "--initial-map");
			for (const auto& w : initialMap->warnings) report("warning: " + w);
			initializeFromSavedMap(builder, *initialMap);
		}
		catch (const std::exception& e)
		{
			reportError(e);
			return kExitInputError;
		}
	CProgress progress(m_err, cl.quiet, cl.progressInterval);
	CRunClock clock;
	TRunSummary run;
	run.input = cl.input;
	run.format = reader->format() == LogFormat::Carmen ? "carmen" : "rawlog";
	run.configIni = runConfigText(cfg, cl.input);
	run.mrptRawlog = reader->format() == LogFormat::MrptRawlog ? cl.input : cl.saveRawlog;
	run.stages.startMapping();
	const double mappingThreadCpu0 = threadCpuSeconds();
	int exitCode = initialMap ? continueInitialMap(*initialMap, cfg, *reader, builder, progress,
												   run, signals)
							  : mapLog(*reader, builder, progress, run, signals);
	exitCode = endOffline(builder, *reader, progress, run, mappingThreadCpu0, exitCode);
	if (builder.stats().scans == 0 && exitCode == kExitOk)
	{
		run.status = nothingToMap(*reader, builder);
		exitCode = kExitInputError;
	}
	finishRunSummary(run, clock, m_warningsTotal);
	writeRunOutputs(builder, cl.outDir, run);
	if (m_icpSlam && builder.stats().scans > 0)
		writeIcpSlamOutputs(cl.outDir, builder.trajectory(), m_scansAfterEntry);
	reportEnd(cl, builder, run, exitCode);
	return exitCode;
}

int CSlamApp::endOffline(CMetricMapBuilderLRGC& builder, CLogReader& reader,
						 CProgress& progress, TRunSummary& run, double threadCpu0, int exitCode)
{
	endMappingStage(run, builder, threadCpu0);
	// The reader's last words: lines skipped after the last entry (a file of malformed lines
	// has nothing else) and the counts of the problems not listed.
	reportWarnings(reader.takeWarnings());

	exitCode = finishMap(builder, run, exitCode);
	reportWarnings(builder.takeWarnings());
	if (!run.initialMap.empty() && run.mergedMap.empty()) reportPiece(builder, run);
	if (exitCode == kExitOk)
		progress.finish(1.0, builder.stats().scans);
	else
		progress.finish(
			reader.fractionRead(), builder.stats().scans,
			exitCode == kExitInterrupted ? "interrupted" : "stopped by an input error");
	run.malformedLines = reader.stats().skippedLines;
	run.logContents = reader.stats().contents;
	return exitCode;
}

// The end of the run (CMetricMapBuilderLRGC::finish: the loop results still due, the revisit
// sweep, the final optimisation). If it fails (a loop search that could not run, such as a
// correlation grid beyond its cell budget, rethrown by the worker) the map as mapped is still
// whole: it is saved, and the run fails with the reason (the first one, if it failed before).
int CSlamApp::finishMap(CMetricMapBuilderLRGC& builder, TRunSummary& run, int exitCode)
{
	const auto t0 = std::chrono::steady_clock::now();
	try
	{
		builder.finish();
	}
	catch (const std::exception& e)
	{
		if (exitCode == kExitOk || exitCode == kExitInterrupted)
			run.status = "error at the end of the run: " + oneLineError(e);
		if (m_verbose) report("details:\n" + errorDetails(e));
		exitCode = kExitInputError;
	}
	run.finalOptimizationSeconds =
		std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
	run.stages.finalOptimization = run.stages.lap();
	return exitCode;
}

int CSlamApp::mapLog(CLogReader& reader, CMetricMapBuilderLRGC& builder, CProgress& progress,
					 TRunSummary& run, const CStopSignalWatcher& signals,
					 const TEntryHook& afterEntry)
{
	while (!signals.stopRequested())
	{
		std::optional<TLogEntry> entry;
		const double readCpu0 = threadCpuSeconds();
		try
		{
			entry = reader.next();
		}
		catch (const std::exception& e)
		{
			run.status = "input error: " + oneLineError(e);
			if (m_verbose) report("details:\n" + errorDetails(e));
			return kExitInputError;
		}
		const double feedCpu0 = threadCpuSeconds();
		run.stages.inputCpu += feedCpu0 - readCpu0;
		if (!entry) break;
		++run.logEntries;
		// rawlog_offset as icp-slam counts it: serialised objects read so far (an action
		// collection and its sensory frame are two); 0 unless ICP-SLAM.ini gives one.
		m_objectsRead +=
			entry->observation || !entry->actions || entry->actions->size() == 0 ? 1 : 2;
		if (m_objectsRead >= m_skipObjects && mapEntry(builder, *entry, run) != kExitOk)
			return kExitInputError;
		run.stages.feedCpu += threadCpuSeconds() - feedCpu0;
		if (afterEntry)
			if (const int code = afterEntry(); code != kExitOk) return code;
		if (m_icpSlam) m_scansAfterEntry.push_back(builder.stats().scans);
		reportWarnings(reader.takeWarnings());
		reportWarnings(builder.takeWarnings());
		progress.update(reader.fractionRead(), builder.stats().scans,
						mrpt::format("kf %zu  loop closures %zu", builder.stats().keyframes,
									 builder.stats().loopClosures));
	}
	if (!signals.stopRequested()) return kExitOk;
	run.status = "interrupted";
	return kExitInterrupted;
}

int CSlamApp::mapEntry(CMetricMapBuilderLRGC& builder, TLogEntry& entry, TRunSummary& run)
{
	const size_t scansBefore = builder.stats().scans;
	const auto t0 = std::chrono::steady_clock::now();
	try
	{
		feedEntry(builder, entry);
	}
	catch (const std::exception& e)
	{
		run.status = "error at " + entry.where + ": " + oneLineError(e);
		if (m_verbose) report("details:\n" + errorDetails(e));
		return kExitInputError;
	}
	if (builder.stats().scans > scansBefore)
	{
		run.latencyMs.push_back(
			std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
				.count());
		run.latencyStamp.push_back(mrpt::Clock::toDouble(builder.lastScanTimestamp()));
	}
	return kExitOk;
}

void CSlamApp::reportEnd(const TSlamCommandLine& cl, const CMetricMapBuilderLRGC& builder,
						 const TRunSummary& run, int exitCode)
{
	const auto& s = builder.stats();
	if (s.scans == 0)
	{
		report("lrgc-slam: " + run.status + "; no map written (counts in " +
			   (std::filesystem::path(cl.outDir) / "stats.json").string() + ")");
		return;
	}
	if (exitCode != kExitOk)
		report("lrgc-slam: " + run.status + " (maps of what was read are saved)");
	if (!cl.quiet || exitCode != kExitOk)
		report(mrpt::format(
			"lrgc-slam: %zu scans, %zu keyframes, %zu loop closures (%zu loop links), %.1f s "
			"of data in %.1f s (%.0fx real time); outputs in %s",
			s.scans, s.keyframes, s.loopClosures, s.loopClosureLinks, run.dataDurationSeconds,
			run.wallSeconds,
			run.wallSeconds > 0 ? run.dataDurationSeconds / run.wallSeconds : 0.0,
			cl.outDir.c_str()));
}

}  // namespace lrgc::apps
