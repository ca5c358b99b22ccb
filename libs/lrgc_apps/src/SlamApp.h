/* CSlamApp: lrgc-slam as a library class, so tests drive the whole application.
 *
 * Offline: streams a log (rawlog or CARMEN) into CMetricMapBuilderLRGC, reports progress,
 * and writes every output atomically into the output directory. A problem the run can go on
 * from (a malformed line, a skipped scan) is reported and skipped; one it cannot (a
 * truncated or corrupt rawlog) ends the run with the maps built so far saved and a non-zero
 * exit status. SIGINT/SIGTERM stop the run the same way, with exit status 130: they are taken
 * by a CStopSignalWatcher, as in a live run, never by a handler (which METIS would reset). A
 * log with no scan to map (no 2D laser scan, or none usable) ends with exit status 1, a line
 * saying what the log holds, and stats.json only: no empty map. A bad --out is refused before
 * the log is opened.
 *
 * Merge (--merge MAP_A MAP_B, SlamAppMerge.cpp): the offline loop, its log MAP_B's keyframes
 * replayed to continue MAP_A (MergeMaps.h); nothing is written unless they join.
 *
 * Live (--live SENSORS.ini): runs the live runner given at construction. It lives in the
 * separate library lrgc_live (live/LiveSlam.h, runLiveSlam), so that only programs
 * that map live link mrpt::hwdrivers and its hundreds of shared libraries.
 */
#pragma once

#include "CommandLine.h"

#include <cstdio>
#include <exception>
#include <functional>
#include <string>
#include <vector>

namespace lrgc
{
class CMetricMapBuilderLRGC;
class CLocalizer;
}  // namespace lrgc

namespace lrgc::apps
{
class CLocalizationRecorder;
class CLogReader;
class CProgress;
class CStopSignalWatcher;
struct TRunSummary;
struct TAppConfig;
struct TLogEntry;
struct TSavedMap;

/** Exit statuses of lrgc-slam. */
enum ExitStatus : int
{
	kExitOk = 0,
	/** The input could not be read to the end (the maps so far are saved), or it holds
	 * nothing to map (no map is written; the message says what it holds). */
	kExitInputError = 1,
	kExitUsage = 2,         //!< bad command line, configuration or --out: nothing was run
	kExitInterrupted = 130  //!< SIGINT/SIGTERM: maps so far saved
};

class CSlamApp
{
public:
	/** Runs `lrgc-slam --live` and returns the exit status; may throw CUsageError. */
	using TLiveRunner = std::function<int(const TSlamCommandLine&, std::FILE* err)>;

	/** err: where progress, warnings and errors go (stderr in the real app). live: the live
	 * runner (lrgc::apps::runLiveSlam); without one, --live is a usage error. */
	explicit CSlamApp(std::FILE* err = stderr, TLiveRunner live = {})
		: m_err(err), m_live(std::move(live))
	{
	}

	/** Runs lrgc-slam with argv without argv[0]; returns the exit status. Never throws. */
	int run(const std::vector<std::string>& args);

private:
	int runOffline(const TSlamCommandLine& cl);
	/** Called after each log entry mapped: kExitOk to go on, else the run's exit code. */
	using TEntryHook = std::function<int()>;
	/** Feeds the log to the builder; returns kExitOk at its end, kExitInputError (run.status
	 * says why) or kExitInterrupted. */
	int mapLog(CLogReader& reader, CMetricMapBuilderLRGC& builder, CProgress& progress,
			   TRunSummary& run, const CStopSignalWatcher& signals,
			   const TEntryHook& afterEntry = {});
	void reportEnd(const TSlamCommandLine& cl, const CMetricMapBuilderLRGC& builder,
				   const TRunSummary& run, int exitCode);
	int convertOnly(const TSlamCommandLine& cl);
	/** builder.finish(); a failure there is kExitInputError (run.status says why), the map
	 * as mapped still to be saved. Returns the run's exit code. */
	int finishMap(CMetricMapBuilderLRGC& builder, TRunSummary& run, int exitCode);
	/** One log entry into the builder, its latency recorded; kExitOk or kExitInputError. */
	int mapEntry(CMetricMapBuilderLRGC& builder, TLogEntry& entry, TRunSummary& run);
	// --- continuing and localising on a saved map (SlamAppSavedMap.cpp) ---
	/** --initial-map: maps the log from its first scan as a piece of its own beside the
	 * map, and joins it to the map where global correlation finds it (CPieceJoiner), all
	 * while mapping; a piece never joined is kept in its own frame (run.frame says which).
	 * `merging` (--merge: the log is MAP_B's keyframes): no "continuing" line, and the search
	 * in hand at the log's end is awaited. Returns mapLog()'s exit code. */
	int continueInitialMap(const TSavedMap& map, const TAppConfig& cfg, CLogReader& reader,
						   CMetricMapBuilderLRGC& builder, CProgress& progress,
						   TRunSummary& run, const CStopSignalWatcher& signals,
						   bool merging = false);
	/** --merge MAP_A MAP_B (SlamAppMerge.cpp): MAP_B's keyframes continue MAP_A as a piece
	 * (MergeMaps.h); exit 1, nothing written, if the piece is never joined. */
	int runMerge(const TSlamCommandLine& cl);
	/** The end of an offline mapping run: the mapping stage's figures, the reader's last
	 * warnings, finishMap(), the builder's warnings, the progress line. */
	int endOffline(CMetricMapBuilderLRGC& builder, CLogReader& reader, CProgress& progress,
				   TRunSummary& run, double threadCpu0, int exitCode);
	/** After finishMap(): a piece never joined is kept, its frame stated (run.frame). */
	void reportPiece(const CMetricMapBuilderLRGC& builder, TRunSummary& run);
	/** --localize: tracks the log on the map (CLocalizer); writes trajectory.tum, timing.csv
	 * and stats.json. */
	int runLocalize(const TSlamCommandLine& cl);
	/** Feeds the log to the localiser until its end (kExitOk), an input error
	 * (kExitInputError, run.status says why) or a stop request (kExitOk: the caller sees it).
	 */
	int localizeLog(CLogReader& reader, CLocalizer& localizer, CLocalizationRecorder& recorder,
					CProgress& progress, TRunSummary& run, const CStopSignalWatcher& signals,
					bool quiet);
	void report(const std::string& line);
	/** "lrgc-slam: <line>"; with --verbose, the details after it. */
	void reportError(const std::string& line, const std::string& details = {});
	void reportError(const std::exception& e);
	/** Shows the first warnings, then only counts them (stats.json has the total). */
	void reportWarnings(const std::vector<std::string>& warnings);

	/** ICP-SLAM.ini [RAWLOG] (IcpSlamIni.h): takes the input, the output folder and the
	 * entries to skip from the .ini into `cl`; reports its ignored settings once. */
	void takeIcpSlamIni(TSlamCommandLine& cl);

	std::FILE* m_err;
	TLiveRunner m_live;
	// --- icp-slam's command line (IcpSlamIni.h) ---
	bool m_icpSlam = false;    //!< also write icp-slam's output files
	size_t m_skipObjects = 0;  //!< [MappingApplication] rawlog_offset
	size_t m_objectsRead = 0;  //!< rawlog objects read so far, as icp-slam counts them
	std::vector<size_t> m_scansAfterEntry;  //!< scans mapped after each log entry
	bool m_verbose = false;
	size_t m_warningsShown = 0, m_warningsTotal = 0;
};

}  // namespace lrgc::apps
