#include "lrgc_apps/live/LiveMapper.h"

#include <mrpt/core/format.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace lrgc::apps
{
namespace
{
constexpr size_t kMaxWarningsShown = 30;

/** The scan as the offline rawlog reader hands it to the builder: NaN, infinite and negative
 * ranges of valid rays marked invalid (see CLogReader::markBadRangesInvalid). A copy is made
 * only when something changes, so the captured object is never modified. */
mrpt::obs::CObservation2DRangeScan::Ptr asOfflineReaderWould(
	const mrpt::obs::CObservation2DRangeScan::Ptr& scan)
{
	auto bad = [&](size_t i)
	{
		const float r = scan->getScanRange(i);
		return scan->getScanRangeValidity(i) && !(std::isfinite(r) && r >= 0);
	};
	size_t i = 0;
	while (i < scan->getScanSize() && !bad(i)) ++i;
	if (i == scan->getScanSize()) return scan;
	auto copy = std::make_shared<mrpt::obs::CObservation2DRangeScan>(*scan);
	for (; i < copy->getScanSize(); ++i)
		if (bad(i)) copy->setScanRangeValidity(i, false);
	return copy;
}

/** A live run takes loop-closing results as [LiveMapping] loop_results_when_ready says. */
lrgc::TLRGCParams liveParams(const TAppConfig& config)
{
	lrgc::TLRGCParams p = config.lrgc;
	p.loop.apply_when_ready = config.live.loop_results_when_ready;
	return p;
}
}  // namespace

CLiveMapper::CLiveMapper(const TAppConfig& config, std::string outDir, std::string sensorsIni,
						 CLiveConsole& console)
	: m_builder(liveParams(config)),
	  m_outDir(std::move(outDir)),
	  m_console(console),
	  m_policy(config.live.max_backlog_scans),
	  m_maxBacklog(config.live.max_backlog_scans)
{
	m_builder.logging_enable_console_output = false;  // warnings are reported below
	m_run.input = std::move(sensorsIni);
	m_run.format = "live";
}

void CLiveMapper::process(const TLiveItem& item, size_t scansBehind)
{
	++m_counts.items;
	++m_run.logEntries;
	if (item.isScan)
	{
		++m_counts.scans;
		const bool wasBehind = m_policy.behind();
		const bool map = m_policy.shouldMap(scansBehind);
		if (!wasBehind && m_policy.behind())
			m_console.message(mrpt::format(
				"live: mapping is behind: %zu scans wait (max_backlog_scans %zu); skipping "
				"scans to keep up, the capture keeps them all",
				scansBehind, m_maxBacklog));
		if (wasBehind && !m_policy.behind())
			m_console.message(
				mrpt::format("live: mapping caught up (%zu scans skipped while behind)",
							 m_policy.skippedThisEpisode()));
		if (map) mapScan(item);
	}
	else if (auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservation>(item.object))
	{
		if (std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(obs))
			++m_counts.odometry;
		else
			++m_counts.otherObservations;
		m_builder.processObservation(obs);
	}
	else
		++m_counts.notObservations;
	reportWarnings();
}

void CLiveMapper::mapScan(const TLiveItem& item)
{
	const auto scan =
		std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(item.object);
	const size_t scansBefore = m_builder.stats().scans;
	const auto t0 = std::chrono::steady_clock::now();
	m_builder.processObservation(asOfflineReaderWould(scan));
	++m_counts.scansMapped;
	const auto t1 = std::chrono::steady_clock::now();
	if (m_builder.stats().scans > scansBefore)
	{
		m_run.latencyMs.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
		m_run.latencyStamp.push_back(mrpt::Clock::toDouble(scan->timestamp));
	}
	m_queueLatencyMs.push_back(
		std::chrono::duration<double, std::milli>(t1 - item.arrived).count());
}

void CLiveMapper::reportWarnings()
{
	for (const auto& w : m_builder.takeWarnings())
	{
		++m_warningsTotal;
		if (m_warningsShown++ < kMaxWarningsShown)
			m_console.message("warning: " + w);
		else if (m_warningsShown == kMaxWarningsShown + 1)
			m_console.message("warning: further warnings are counted in stats.json, not shown");
	}
}

void CLiveMapper::finish()
{
	const auto t0 = std::chrono::steady_clock::now();
	m_builder.finish();
	m_run.finalOptimizationSeconds =
		std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

TRunOutputsSnapshot CLiveMapper::snapshot(const std::string& status) const
{
	TRunSummary run = m_run;
	run.status = status;
	finishRunSummary(run, m_clock, m_warningsTotal);
	return snapshotRunOutputs(m_builder, std::move(run));
}

}  // namespace lrgc::apps
