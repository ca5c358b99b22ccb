/* Localisation's outputs (--localize, on a log or live): trajectory.tum, timing.csv (once a
 * scan was localised), stats.json and config.ini in the output folder, each written
 * atomically.
 *
 * Memory flat however long the run. What can no longer change is written out as it comes:
 * the localiser's settled poses (CLocalizer::takeSettledPoses) and every scan's timing row are
 * appended to two stream files in the output folder (.trajectory.tum.stream,
 * .timing.csv.stream), and stats.json's latency figures come from a fixed histogram
 * (CLatencyHistogram), so nothing is kept per scan. A save (periodic in a live run, and the
 * last one) publishes each output atomically: the stream's bytes written so far, then the
 * poses still open, into a temporary file renamed over the output (atomic_file.h). The
 * streams are removed when the recorder ends; a run killed outright leaves them behind
 * (hidden files, never read back).
 */
#pragma once

#include <lrgc/localization/Localizer.h>
#include <lrgc_apps/RunOutputs.h>
#include <lrgc_apps/RunStats.h>
#include "LatencyHistogram.h"

#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>

namespace lrgc::apps
{
struct TAppConfig;
struct TSavedMap;

/** CPU time of the calling thread [ms] (POSIX): a scan's own work, without the time the
 * machine gave other processes meanwhile. */
double threadCpuMs();

/** One localised scan's costs [ms], as timing.csv lists them. */
struct TScanTiming
{
	double stamp = 0;  //!< the scan's timestamp [s]
	double latencyMs = 0, replayWaitMs = 0, cpuMs = 0;
};

/** What a save writes, taken on the localising thread, written on any (writeLocalizationSave).
 */
struct TLocalizationSave
{
	std::string outDir, configIni, statsJson;
	bool localized = false;  //!< a scan has a map pose: trajectory.tum and timing.csv written
	std::string trajectoryStream, timingStream;     //!< the stream files
	uint64_t trajectoryBytes = 0, timingBytes = 0;  //!< their lengths at the snapshot
	std::string trajectoryTail;                     //!< TUM rows of the poses still open
};

/** Writes every output of `save`, each atomically. */
void writeLocalizationSave(const TLocalizationSave& save);

/** A localiser on a saved map: its keyframes and graph as a map builder restores them
 * (initializeFromSavedMap), with the run's parameters; console output off. */
std::unique_ptr<CLocalizer> localizerOnSavedMap(const TSavedMap& map, const TAppConfig& cfg);

/** "no start found in the map 'M': N scans read, K global correlation attempts rejected
 * (last: ...); ..." */
std::string noStartMessage(const std::string& map, size_t scans, size_t attempts,
						   const std::string& lastRejection);

/** The console line of a localisation event ("lrgc-slam: t=12.345 lost at (...)"). */
std::string localizationEventLine(const TLocalizationEvent& e);

class CLocalizationRecorder
{
public:
	/** Creates the stream files in `outDir` (made if missing); throws if it cannot. */
	explicit CLocalizationRecorder(const std::string& outDir);
	~CLocalizationRecorder();  //!< removes the stream files
	CLocalizationRecorder(const CLocalizationRecorder&) = delete;
	CLocalizationRecorder& operator=(const CLocalizationRecorder&) = delete;

	/** A scan processed: its timing row, and the poses it settled (written out). */
	void addScan(const TScanTiming& timing, CLocalizer& localizer);
	/** Everything a save writes, as of now. `run`: its status, input, counts and times (its
	 * per-scan vectors are not used); `map`: the map localised on. */
	TLocalizationSave snapshot(const CLocalizer& localizer, TRunSummary run,
							   const std::string& map);

private:
	struct TStream
	{
		std::string path;
		std::FILE* file = nullptr;
		uint64_t bytes = 0;
	};
	void append(TStream& s, const std::string& text);
	void flush(TStream& s);

	std::string m_outDir;
	TStream m_trajectory, m_timing;
	CLatencyHistogram m_latency;
	double m_cpuMaxMs = 0;
	double m_firstStamp = 0, m_lastStamp = 0;  //!< earliest and latest scan timed [s]
};

}  // namespace lrgc::apps
