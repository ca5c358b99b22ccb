/* lrgc-slam on a saved map: --initial-map (continue it) and --localize (track on it).
 * The map is an earlier output folder or any .simplemap (SavedMap.h); in both cases the log's
 * start in it is unknown and found by global correlation (lrgc/localization). */
#include "AppConfig.h"
#include "ErrorText.h"
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
/** CPU time of the calling thread [ms] (POSIX): a scan's own work, without the time the
 * machine gave other processes meanwhile. */
double threadCpuMs()
{
	timespec t{};
	clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
	return 1e3 * double(t.tv_sec) + 1e-6 * double(t.tv_nsec);
}

/** Per localised scan, as TRunSummary::latencyMs: the replay's wait for the search worker
 * (not in latencyMs) and the tracking thread's CPU time [ms]. */
struct TScanCosts
{
	std::vector<double> replayWaitMs, cpuMs;
};

std::string noStartMessage(const std::string& map, size_t scans, size_t attempts,
						   const std::string& lastRejection)
{
	return mrpt::format(
		"no start found in the map '%s': %zu scans read, %zu global correlation attempts "
		"rejected (last: %s); the log may begin outside the mapped area",
		map.c_str(), scans, attempts, lastRejection.empty() ? "none" : lastRejection.c_str());
}
}  // namespace

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
std::string jsonQuote(const std::string& s)
{
	std::string out = "\"";
	for (const char ch : s)
		if (ch == '"' || ch == '\\')
			out += '\\', out += ch;
		else if (static_cast<unsigned char>(ch) < 0x20)
			out += mrpt::format("\\u%04x", ch);
		else
			out += ch;
	return out + "\"";
}

// One line per event: what a navigation stack is told (lost, kidnapped, relocalised, ...).
std::string eventsJson(const std::vector<TLocalizationEvent>& events)
{
	std::string j = "[";
	for (size_t i = 0; i < events.size(); ++i)
	{
		const auto& e = events[i];
		j += mrpt::format(
			"%s\n    {\"event\": \"%s\", \"stamp\": %.6f, \"pose\": [%.4f, %.4f, %.2f], "
			"\"jump_m\": %.3f, \"search_half_window_m\": %.2f}",
			i ? "," : "", e.name(), e.stamp, e.pose.x, e.pose.y, mrpt::RAD2DEG(e.pose.phi),
			e.jump_m, e.window_m);
	}
	return j + (events.empty() ? "]" : "\n  ]");
}

std::string localizationStatsJson(const CLocalizer& loc, const TRunSummary& run,
								  const TScanCosts& costs, const std::string& map)
{
	const double cpuMax =
		costs.cpuMs.empty() ? 0 : *std::max_element(costs.cpuMs.begin(), costs.cpuMs.end());
	const TLocalizerStats& s = loc.stats();
	const TLatencySummary lat = summarizeLatencies(run.latencyMs);
	std::ostringstream j;
	j.precision(6);
	j << std::fixed << "{\n"
	  << "  \"mode\": \"localize\",\n"
	  << "  \"input\": " << jsonQuote(run.input) << ",\n"
	  << "  \"map\": " << jsonQuote(map) << ",\n"
	  << "  \"status\": " << jsonQuote(run.status) << ",\n"
	  << "  \"log_entries\": " << run.logEntries << ",\n"
	  << "  \"scans\": " << s.scans << ",\n"
	  << "  \"localized_scans\": " << s.localizedScans << ",\n"
	  << "  \"scans_before_start\": " << s.scansBeforeStart << ",\n"
	  << "  \"good_matches\": " << s.goodMatches << ",\n"
	  << "  \"poor_matches\": " << s.poorMatches << ",\n"
	  << "  \"placed_by_recent_scans\": " << s.recentMatches << ",\n"
	  << "  \"lost\": " << s.lostEvents << ",\n"
	  << "  \"kidnapped\": " << s.kidnapEvents << ",\n"
	  << "  \"relocalizations\": " << s.relocalizations << ",\n"
	  << "  \"recovered_by_tracking\": " << s.recoveredByTracking << ",\n"
	  << "  \"global_localization\": {\"attempts\": " << s.globalAttempts
	  << ", \"total_s\": " << s.globalSeconds << ", \"modelled_s\": " << s.globalModelledSeconds
	  << ", \"replay_wait_s\": " << s.replayWaitSeconds
	  << ", \"replay_wait_max_ms\": " << 1e3 * s.replayWaitMaxSeconds
	  << ", \"on_tracking_thread\": " << s.searchesOnTrackingThread
	  << ", \"scans_during_searches\": " << s.scansDuringSearches << "},\n"
	  << "  \"events\": " << eventsJson(s.events) << ",\n"
	  << "  \"warnings\": " << run.warnings << ",\n"
	  << "  \"data_duration_s\": " << run.dataDurationSeconds << ",\n"
	  << "  \"wall_time_s\": " << run.wallSeconds << ",\n"
	  << "  \"cpu_time_s\": " << run.cpuSeconds << ",\n"
	  << "  \"peak_rss_mb\": " << run.peakRssMiB << ",\n"
	  << "  \"latency_ms\": {\"median\": " << lat.median_ms << ", \"p99\": " << lat.p99_ms
	  << ", \"max\": " << lat.max_ms << ", \"mean\": " << lat.mean_ms
	  << ", \"cpu_max\": " << cpuMax << "}\n"
	  << "}\n";
	return j.str();
}
}  // namespace

namespace
{
// --localize's outputs in cl.outDir (never the map's folder: checked before the run): the
// trajectory and the per-scan latencies once a scan was localised, the configuration, stats.
void writeLocalizationOutputs(const CLocalizer& localizer, const TRunSummary& run,
							  const TScanCosts& costs, const TAppConfig& cfg,
							  const TSlamCommandLine& cl)
{
	namespace fs = std::filesystem;
	fs::create_directories(cl.outDir);
	const auto path = [&](const char* name) { return (fs::path(cl.outDir) / name).string(); };
	if (!localizer.trajectory().empty())
	{
		writeTrajectoryTum(localizer.trajectory(), path("trajectory.tum"));
		std::string csv = "scan_index,timestamp,latency_ms,replay_wait_ms,cpu_ms\n";
		for (size_t i = 0; i < run.latencyMs.size(); ++i)
			csv += mrpt::format("%zu,%.6f,%.4f,%.4f,%.4f\n", i, run.latencyStamp[i],
								run.latencyMs[i], costs.replayWaitMs[i], costs.cpuMs[i]);
		writeTextFileAtomically(path("timing.csv"), csv);
	}
	writeTextFileAtomically(path(kRunConfigFile), runConfigText(cfg, cl.input));
	writeTextFileAtomically(path("stats.json"),
							localizationStatsJson(localizer, run, costs, cl.localize));
}
}  // namespace

namespace
{
std::string eventLine(const TLocalizationEvent& e)
{
	std::string line =
		mrpt::format("lrgc-slam: t=%.3f %s at (%.2f m, %.2f m, %.1f deg)", e.stamp, e.name(),
					 e.pose.x, e.pose.y, mrpt::RAD2DEG(e.pose.phi));
	if (e.kind == TLocalizationEvent::Kind::Relocalized)
		line += mrpt::format(": the pose moved %.2f m", e.jump_m);
	return line;
}

// A localiser on the saved map: its keyframes and graph as a map builder restores them.
std::unique_ptr<CLocalizer> localizerOn(const TSavedMap& map, const TAppConfig& cfg)
{
	CMetricMapBuilderLRGC restored(cfg.lrgc);
	restored.logging_enable_console_output = false;
	initializeFromSavedMap(restored, map);
	auto localizer = std::make_unique<CLocalizer>(restored.graph(), restored.keyframes(),
												  cfg.lrgc, cfg.localization);
	localizer->logging_enable_console_output = false;
	return localizer;
}

// One log entry fed to the localiser. For a scan: its latency (its processing, without the
// replay's wait for the modelled search worker, CGlobalSearchWorker, which is listed apart),
// that wait and the thread's CPU time [ms].
void feedTimed(CLocalizer& localizer, TLogEntry& entry, TRunSummary& run,
			   std::vector<double>& replayWaitMs, std::vector<double>& cpuMs)
{
	const size_t scansBefore = localizer.stats().scans;
	const auto t0 = std::chrono::steady_clock::now();
	const double cpu0 = threadCpuMs();
	feedEntry(localizer, entry);
	if (localizer.stats().scans == scansBefore) return;
	const double waitMs = 1e3 * localizer.lastReplayWaitSeconds();
	run.latencyMs.push_back(
		std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
			.count() -
		waitMs);
	replayWaitMs.push_back(waitMs);
	cpuMs.push_back(threadCpuMs() - cpu0);
	run.latencyStamp.push_back(mrpt::Clock::toDouble(localizer.lastScanTimestamp()));
}
}  // namespace

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
		localizer = localizerOn(map, cfg);
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
	std::vector<double> replayWaitMs, cpuMs;  // per scan, as run.latencyMs
	int exitCode = kExitOk;
	while (!signals.stopRequested())
	{
		std::optional<TLogEntry> entry;
		try
		{
			entry = reader->next();
		}
		catch (const std::exception& e)
		{
			run.status = "input error: " + oneLineError(e);
			exitCode = kExitInputError;
			break;
		}
		if (!entry) break;
		++run.logEntries;
		const size_t eventsBefore = localizer->stats().events.size();
		feedTimed(*localizer, *entry, run, replayWaitMs, cpuMs);
		const auto& events = localizer->stats().events;  // what a navigation stack hears
		for (size_t i = eventsBefore; i < events.size() && !cl.quiet; ++i)
			report(eventLine(events[i]));
		reportWarnings(reader->takeWarnings());
		const auto& s = localizer->stats();
		progress.update(reader->fractionRead(), s.scans,
						mrpt::format("localised %zu  lost %zu  relocalised %zu",
									 s.localizedScans, s.lostEvents, s.relocalizations));
	}
	if (signals.stopRequested()) run.status = "interrupted", exitCode = kExitInterrupted;
	const TLocalizerStats& s = localizer->stats();
	if (exitCode == kExitOk && !s.started)
	{
		run.status = noStartMessage(cl.localize, s.scans, s.globalAttempts, s.lastRejection);
		exitCode = kExitInputError;
	}
	progress.finish(exitCode == kExitOk ? 1.0 : reader->fractionRead(), s.scans);
	finishRunSummary(run, clock, m_warningsTotal);
	writeLocalizationOutputs(*localizer, run, {replayWaitMs, cpuMs}, cfg, cl);
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
