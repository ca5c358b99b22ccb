/* CLiveProcessor: what a live run does with the observations it takes from the queue: map
 * them (CLiveMapper, which may continue a saved map) or localise the robot on a saved map
 * (CLiveLocalizer). This base does what both do: the keep-up policy for laser scans
 * ([LiveMapping] max_backlog_scans: skipped scans are said and counted, the capture keeps
 * them), the scan prepared as the offline reader prepares it (NaN, infinite and negative
 * ranges marked invalid, on a copy, so that the capture keeps what the driver sent), counts,
 * the queue latency, and the warnings shown on the console (the first 30, then counted).
 *
 * Saving: saveJob() runs on the processing thread, between two scans, and copies what the
 * outputs need (a snapshot); the job it returns writes them, each atomically, on the saver
 * thread (CLiveSaver) or, for the last save, on this thread.
 */
#pragma once

#include <lrgc/common/StopToken.h>
#include "AppConfig.h"
#include "LatencyHistogram.h"
#include "live/KeepUpPolicy.h"
#include "live/LiveConsole.h"
#include "live/LiveQueues.h"

#include <mrpt/obs/CObservation.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <functional>
#include <string>
#include <vector>

namespace lrgc::apps
{
struct TLiveMapperCounts
{
	size_t items = 0;              //!< objects taken from the queue
	size_t scans = 0;              //!< laser scans taken
	size_t scansMapped = 0;        //!< laser scans processed (not skipped to keep up)
	size_t odometry = 0;           //!< odometry observations processed
	size_t otherObservations = 0;  //!< other observations given on (ignored there)
	size_t notObservations = 0;    //!< captured objects that are not observations (not used)
};

class CLiveProcessor
{
public:
	/** `activity`: "mapping" or "localisation", as the console messages name it. */
	CLiveProcessor(const TAppConfig& config, CLiveConsole& console, const char* activity);
	virtual ~CLiveProcessor() = default;

	/** Processes (or, by the keep-up policy, skips) one item; `scansBehind` laser scans wait
	 * after it. Throws if processing fails. */
	void process(const TLiveItem& item, size_t scansBehind);
	/** After the stop, before the last save: the final optimisation of a map. */
	virtual void finish() = 0;
	/** Why the run cannot end well ("no start found in the map ..."), or empty. */
	virtual std::string failure() const = 0;
	/** A scan was processed: a save has something to write. */
	virtual bool anyScan() const = 0;
	/** Snapshot now (stats.json says `status`); the job writes every output and returns what
	 * it saved ("maps saved (120 scans, 14 keyframes)"). See the file comment. */
	virtual std::function<std::string()> saveJob(const std::string& status) = 0;
	/** The status line's part on the processing: "mapped 120, queue 0, loop closures 2". */
	virtual std::string statusText(size_t queueDepth) const = 0;
	/** The closing line's part: what was mapped or localised. */
	virtual std::string summaryText() const = 0;
	/** The computation in hand and those after it end early once `stop` is stopped. */
	virtual void setStopToken(const CStopToken& stop) = 0;

	const TLiveMapperCounts& counts() const { return m_counts; }
	const CKeepUpPolicy& policy() const { return m_policy; }
	/** Queue latency (arrival to processed) of processed scans [ms], in fixed memory. */
	const CLatencyHistogram& queueLatency() const { return m_queueLatency; }
	size_t warnings() const { return m_warningsTotal; }

protected:
	/** A scan prepared as the offline reader would, not skipped. */
	virtual void processScan(const mrpt::obs::CObservation2DRangeScan::Ptr& scan) = 0;
	/** Odometry and other observations. */
	virtual void processOther(const mrpt::obs::CObservation::Ptr& obs) = 0;
	/** Warnings raised since the last call (the map builder's). */
	virtual std::vector<std::string> takeWarnings() = 0;
	/** A console line, shown whatever the verbosity if `important`. */
	void message(const std::string& line, bool important = true);

private:
	void reportWarnings();

	const char* m_activity;
	CLiveConsole& m_console;
	CKeepUpPolicy m_policy;
	size_t m_maxBacklog;
	TLiveMapperCounts m_counts;
	CLatencyHistogram m_queueLatency;
	size_t m_warningsShown = 0, m_warningsTotal = 0;
};

}  // namespace lrgc::apps
