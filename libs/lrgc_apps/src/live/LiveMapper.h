/* CLiveMapper: the mapping side of a live run. It owns the same map builder as an offline run
 * (CMetricMapBuilderLRGC, fed with processObservation() exactly as an observations-only rawlog
 * is fed offline), applies the keep-up policy to laser scans, and takes the snapshots of
 * every output that the live saver writes (CLiveSaver), periodically and at the end.
 *
 * Same map as a replay. A scan is prepared for the builder as the offline rawlog reader
 * prepares it (NaN, infinite or negative ranges marked invalid; scans with fewer than 2 rays
 * never reach the mapper, see CSensorSupervisor), on a copy so that the capture keeps what the
 * driver sent. So when no scan was skipped, `lrgc-slam --input DIR/capture.rawlog` feeds the
 * builder the same observations in the same order and gives the same trajectory and maps.
 */
#pragma once

#include <lrgc/map_builder/CMetricMapBuilderLRGC.h>
#include "AppConfig.h"
#include <lrgc_apps/RunOutputs.h>
#include <lrgc_apps/RunStats.h>
#include "live/KeepUpPolicy.h"
#include "live/LiveConsole.h"
#include "live/LiveQueues.h"

#include <string>
#include <vector>

namespace lrgc::apps
{
struct TLiveMapperCounts
{
	size_t items = 0;              //!< objects taken from the queue
	size_t scans = 0;              //!< laser scans taken
	size_t scansMapped = 0;        //!< laser scans given to the builder
	size_t odometry = 0;           //!< odometry observations given to the builder
	size_t otherObservations = 0;  //!< other observations given to it (it ignores them)
	size_t notObservations = 0;    //!< captured objects that are not observations (not mapped)
};

class CLiveMapper
{
public:
	CLiveMapper(const TAppConfig& config, std::string outDir, std::string sensorsIni,
				CLiveConsole& console);

	/** Maps (or, by the keep-up policy, skips) one item; `scansBehind` laser scans wait after
	 * it. Throws if the builder fails. */
	void process(const TLiveItem& item, size_t scansBehind);
	/** Every output as of now, with `status` in stats.json (writeRunOutputs); after finish()
	 * for the final save. On the mapping thread: it copies poses and counters, shares scans. */
	TRunOutputsSnapshot snapshot(const std::string& status) const;
	/** Final optimisation of the whole graph (as at the end of an offline run). */
	void finish();

	const CMetricMapBuilderLRGC& builder() const { return m_builder; }
	const std::string& outDir() const { return m_outDir; }
	const TLiveMapperCounts& counts() const { return m_counts; }
	const CKeepUpPolicy& policy() const { return m_policy; }
	/** Queue latency (arrival to mapped) of mapped scans [ms]. */
	const std::vector<double>& queueLatencyMs() const { return m_queueLatencyMs; }
	size_t warnings() const { return m_warningsTotal; }

private:
	void mapScan(const TLiveItem& item);
	void reportWarnings();

	CMetricMapBuilderLRGC m_builder;
	std::string m_outDir;
	CLiveConsole& m_console;
	CKeepUpPolicy m_policy;
	size_t m_maxBacklog;
	TLiveMapperCounts m_counts;
	TRunSummary m_run;
	CRunClock m_clock;
	std::vector<double> m_queueLatencyMs;
	size_t m_warningsShown = 0, m_warningsTotal = 0;
};

}  // namespace lrgc::apps
