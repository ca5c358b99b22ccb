/* lrgc-slam on a saved map: --initial-map (continue it) and --localize (track on it).
 * The map is an earlier output folder or any .simplemap (SavedMap.h); in both cases the log's
 * start in it is unknown and found by global correlation (lrgc/localization). */
#include "AppConfig.h"
#include "ErrorText.h"
#include "LocalizationOutputs.h"
#include "PieceReports.h"
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
#include <limits>
#include <filesystem>
#include <sstream>

namespace lrgc::apps
{

int CSlamApp::continueInitialMap(const TSavedMap& map, const TAppConfig& cfg,
								 CLogReader& reader, CMetricMapBuilderLRGC& builder,
								 CProgress& progress, TRunSummary& run,
								 const CStopSignalWatcher& signals, bool merging)
{
	const std::string continuing = continuingMessage(map, builder, run);
	if (!merging) report("lrgc-slam: " + continuing);
	CPieceJoiner joiner(builder.graph(), builder.keyframes(), cfg.lrgc.correlator,
						cfg.localization);
	joiner.setStopToken(signals.token());
	builder.freezeMap();
	builder.startPiece();
	// After each log entry at log time `now` [s]: the search result due by then, if any.
	const auto joinIfFound = [&](double now) -> int
	{
		if (!builder.pieceFirstNode()) return kExitOk;  // joined
		std::optional<TPieceJoin> join;
		try
		{
			join = joiner.service(builder, now);
			if (join)
				run.pieceInMap = builder.joinPiece(join->node, join->nodeInMap, join->cov);
		}
		catch (const std::exception& e)
		{
			run.status = "error joining the log to the map: " + oneLineError(e);
			return kExitInputError;
		}
		if (!join) return kExitOk;
		const std::string joined = joinMessage(*join, joiner, builder, run);
		report("lrgc-slam: " + (merging ? mergeJoinMessage(run) : joined));
		return kExitOk;
	};
	int exitCode = mapLog(
		reader, builder, progress, run, signals,
		[&]() { return joinIfFound(mrpt::Clock::toDouble(builder.lastScanTimestamp())); });
	// A merge has no later data to wait for: the search in hand is taken whenever it ends
	// (and a patch still due is tried), rather than dropped with the log's end.
	for (int i = 0; merging && exitCode == kExitOk && i < 2 && !signals.stopRequested(); ++i)
		exitCode = joinIfFound(std::numeric_limits<double>::max());
	recordJoinerFigures(joiner, builder, run);
	return exitCode;
}

// At the end of a run continuing a map: a piece never joined is kept, and said so.
void CSlamApp::reportPiece(const CMetricMapBuilderLRGC& builder, TRunSummary& run)
{
	const std::string kept = keptPieceMessage(builder, run);
	if (!kept.empty()) report("lrgc-slam: " + kept);
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
	CProgress progress(m_err, cl.quiet, cl.progressInterval);
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
