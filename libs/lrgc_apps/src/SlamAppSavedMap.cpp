/* lrgc-slam on a saved map: --initial-map (continue it) and --localize (track on it).
 * The map is an earlier output folder or any .simplemap (SavedMap.h); in both cases the log's
 * start in it is unknown and found by global correlation (lrgc/localization). */
#include "AppConfig.h"
#include "ErrorText.h"
#include "LocalizationOutputs.h"
#include "lrgc_apps/MapExport.h"
#include "Progress.h"
#include "RunConfigFile.h"
#include "lrgc_apps/RunOutputs.h"
#include "lrgc_apps/RunStats.h"
#include "lrgc_apps/SavedMap.h"
#include "SlamApp.h"
#include "StopSignalWatcher.h"
#include "atomic_file.h"
#include "lrgc_apps/io/LogReader.h"

#include <lrgc/common/se2.h>
#include <lrgc/localization/Localizer.h>
#include <lrgc/localization/PieceJoiner.h>
#include <lrgc/map_builder/CMetricMapBuilderLRGC.h>
#include <mrpt/obs/CActionCollection.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <sstream>

namespace lrgc::apps
{

namespace
{
// The frame the poses of a piece not joined to the map are stated in (startPiece).
std::string pieceFrame(const CMetricMapBuilderLRGC& builder)
{
	const auto trajectory = builder.trajectory();
	if (trajectory.empty()) return "the log's own frame";
	const TPose2D& first = trajectory.front().robotInMap;
	return mrpt::format(
		"the log's own frame (its first scan at (%.2f m, %.2f m, %.1f deg), its odometry pose)",
		first.x, first.y, mrpt::RAD2DEG(first.phi));
}
}  // namespace

int CSlamApp::continueInitialMap(const TSavedMap& map, const TAppConfig& cfg,
								 CLogReader& reader, CMetricMapBuilderLRGC& builder,
								 CProgress& progress, TRunSummary& run,
								 const CStopSignalWatcher& signals)
{
	run.initialMap = map.path;
	run.initialMapKeyframes = builder.graph().numNodes();
	report(mrpt::format(
		"lrgc-slam: continuing '%s': %zu keyframes, %zu links (%s); the log is mapped as a "
		"piece of its own until global correlation joins it to the map",
		map.path.c_str(), builder.graph().numNodes(), builder.graph().numLinks(),
		map.graph ? "the saved graph" : "linked anew from the keyframes' poses"));
	CPieceJoiner joiner(builder.graph(), builder.keyframes(), cfg.lrgc.correlator,
						cfg.localization);
	joiner.setStopToken(signals.token());
	builder.freezeMap();
	builder.startPiece();
	const auto joinIfFound = [&]() -> int
	{
		if (!builder.pieceFirstNode()) return kExitOk;  // joined
		std::optional<TPieceJoin> join;
		try
		{
			join = joiner.service(builder, mrpt::Clock::toDouble(builder.lastScanTimestamp()));
			if (join) builder.joinPiece(join->node, join->nodeInMap, join->cov);
		}
		catch (const std::exception& e)
		{
			run.status = "error joining the log to the map: " + oneLineError(e);
			return kExitInputError;
		}
		if (join) reportJoin(*join, joiner, builder, run);
		return kExitOk;
	};
	const int exitCode = mapLog(reader, builder, progress, run, signals, joinIfFound);
	run.startAttempts = joiner.attempts();
	run.startSeconds = joiner.secondsSpent();
	run.joinReplayWaitSeconds = joiner.replayWaitSeconds();
	run.lastJoinRejection = joiner.lastRejection();
	if (!run.joined) run.startScans = builder.stats().scans;
	return exitCode;
}

void CSlamApp::reportJoin(const TPieceJoin& join, const CPieceJoiner& joiner,
						  const CMetricMapBuilderLRGC& builder, TRunSummary& run)
{
	run.joined = true;
	run.frame = "map";
	run.startScans = builder.stats().scans;
	const TPose2D start = builder.trajectory().front().robotInMap;
	report(mrpt::format(
		"lrgc-slam: the log starts at (%.2f m, %.2f m, %.1f deg) in the map: joined after %zu "
		"scans, %zu attempts, %.1f s (score %.2f, ambiguity %.2f, patch of %zu keyframes)",
		start.x, start.y, mrpt::RAD2DEG(start.phi), run.startScans, joiner.attempts(),
		joiner.secondsSpent(), join.score, join.ambiguity, join.patchKeyframes));
}

// At the end of a run continuing a map: a piece never joined is kept, and said so.
void CSlamApp::reportPiece(const CMetricMapBuilderLRGC& builder, TRunSummary& run)
{
	if (run.joined || !builder.pieceFirstNode() || builder.stats().scans == 0) return;
	run.frame = pieceFrame(builder);
	report(mrpt::format(
		"lrgc-slam: the log was not joined to the map '%s' (%zu global correlation attempts, "
		"last: %s): kept, its keyframes %zu..%zu and trajectory.tum stated in %s",
		run.initialMap.c_str(), run.startAttempts,
		run.lastJoinRejection.empty() ? "none" : run.lastJoinRejection.c_str(),
		*builder.pieceFirstNode(), builder.graph().numNodes() - 1, run.frame.c_str()));
}

namespace
{
// One log entry fed to the localiser. For a scan, its row for the recorder: its latency (its
// processing, without the replay's wait for the modelled search worker, CGlobalSearchWorker,
// which is listed apart), that wait and the thread's CPU time [ms].
void feedTimed(CLocalizer& localizer, TLogEntry& entry, CLocalizationRecorder& recorder)
{
	const size_t scansBefore = localizer.stats().scans;
	const auto t0 = std::chrono::steady_clock::now();
	const double cpu0 = threadCpuMs();
	feedEntry(localizer, entry);
	if (localizer.stats().scans == scansBefore) return;
	TScanTiming t;
	t.replayWaitMs = 1e3 * localizer.lastReplayWaitSeconds();
	t.latencyMs =
		std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
			.count() -
		t.replayWaitMs;
	t.cpuMs = threadCpuMs() - cpu0;
	t.stamp = mrpt::Clock::toDouble(localizer.lastScanTimestamp());
	recorder.addScan(t, localizer);
}
}  // namespace

int CSlamApp::localizeLog(CLogReader& reader, CLocalizer& localizer,
						  CLocalizationRecorder& recorder, CProgress& progress,
						  TRunSummary& run, const CStopSignalWatcher& signals, bool quiet)
{
	while (!signals.stopRequested())
	{
		std::optional<TLogEntry> entry;
		try
		{
			entry = reader.next();
		}
		catch (const std::exception& e)
		{
			run.status = "input error: " + oneLineError(e);
			return kExitInputError;
		}
		if (!entry) break;
		++run.logEntries;
		const size_t eventsBefore = localizer.stats().events.size();
		feedTimed(localizer, *entry, recorder);
		const auto& events = localizer.stats().events;  // what a navigation stack hears
		for (size_t i = eventsBefore; i < events.size() && !quiet; ++i)
			report(localizationEventLine(events[i]));
		reportWarnings(reader.takeWarnings());
		const auto& s = localizer.stats();
		progress.update(reader.fractionRead(), s.scans,
						mrpt::format("localised %zu  lost %zu  relocalised %zu",
									 s.localizedScans, s.lostEvents, s.relocalizations));
	}
	return kExitOk;
}

int CSlamApp::runLocalize(const TSlamCommandLine& cl)
{
	const TAppConfig cfg = loadAppConfig(cl);
	for (const auto& w : cfg.warnings) report("warning: " + w);  // old key names, all shown
	// Before the reader's guard process, which inherits its mask.
	const CStopSignalWatcher signals;
	std::unique_ptr<CLogReader> reader;
	std::unique_ptr<CLocalizer> localizer;
	try
	{
		reader = openLog(cl.input, cfg.reader);
		const TSavedMap map = loadSavedMap(cl.localize, "--localize");
		for (const auto& w : map.warnings) report("warning: " + w);
		localizer = localizerOnSavedMap(map, cfg);
		localizer->setStopToken(signals.token());
	}
	catch (const std::exception& e)
	{
		reportError(e);
		return kExitInputError;
	}
	CProgress progress(m_err, cl.quiet);
	CRunClock clock;
	TRunSummary run;
	run.input = cl.input;
	run.configIni = runConfigText(cfg, cl.input);
	std::optional<CLocalizationRecorder> recorder;
	try
	{
		recorder.emplace(cl.outDir);
	}
	catch (const std::exception& e)
	{
		reportError(e);
		return kExitInputError;
	}
	int exitCode =
		localizeLog(*reader, *localizer, *recorder, progress, run, signals, cl.quiet);
	if (signals.stopRequested()) run.status = "interrupted", exitCode = kExitInterrupted;
	const TLocalizerStats& s = localizer->stats();
	if (exitCode == kExitOk && !s.started)
	{
		run.status = noStartMessage(cl.localize, s.scans, s.globalAttempts, s.lastRejection);
		exitCode = kExitInputError;
	}
	progress.finish(exitCode == kExitOk ? 1.0 : reader->fractionRead(), s.scans);
	finishRunSummary(run, clock, m_warningsTotal);
	writeLocalizationSave(recorder->snapshot(*localizer, run, cl.localize));
	if (exitCode != kExitOk) report("lrgc-slam: " + run.status);
	if (!cl.quiet || exitCode != kExitOk)
		report(mrpt::format(
			"lrgc-slam: localised %zu of %zu scans on '%s' (start after %zu scans, lost %zu "
			"times, %zu relocalisations); outputs in %s",
			s.localizedScans, s.scans, cl.localize.c_str(), s.scansBeforeStart, s.lostEvents,
			s.relocalizations, cl.outDir.c_str()));
	return exitCode;
}

}  // namespace lrgc::apps
