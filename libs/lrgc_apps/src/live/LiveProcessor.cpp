/* CLiveProcessor (see LiveProcessor.h). */
#include "live/LiveProcessor.h"

#include <mrpt/core/format.h>
#include <mrpt/obs/CObservationOdometry.h>

#include <chrono>
#include <cmath>
#include <string>

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
}  // namespace

CLiveProcessor::CLiveProcessor(const TAppConfig& config, CLiveConsole& console,
							   const char* activity)
	: m_activity(activity),
	  m_console(console),
	  m_policy(config.live.max_backlog_scans),
	  m_maxBacklog(config.live.max_backlog_scans)
{
}

void CLiveProcessor::message(const std::string& line, bool important)
{
	m_console.message(line, important);
}

void CLiveProcessor::process(const TLiveItem& item, size_t scansBehind)
{
	++m_counts.items;
	if (item.isScan)
	{
		++m_counts.scans;
		const bool wasBehind = m_policy.behind();
		const bool use = m_policy.shouldMap(scansBehind);
		if (!wasBehind && m_policy.behind())
			message(mrpt::format(
				"live: %s is behind: %zu scans wait (max_backlog_scans %zu); skipping scans to "
				"keep up, the capture keeps them all",
				m_activity, scansBehind, m_maxBacklog));
		if (wasBehind && !m_policy.behind())
			message(mrpt::format("live: %s caught up (%zu scans skipped while behind)",
								 m_activity, m_policy.skippedThisEpisode()));
		if (use && m_counts.scansMapped == 0 && m_counts.odometry == 0)
			message(
				mrpt::format("live: no odometry before the first scan: each scan's pose "
							 "is predicted by the constant-velocity model ([MotionPredictor] "
							 "cv_sigma_*) and corrected by scan matching (%s)",
							 m_activity == std::string("mapping")
								 ? "local registration"
								 : "against the map, else the recent scans"),
				false);
		if (use)
		{
			processScan(asOfflineReaderWould(
				std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(item.object)));
			++m_counts.scansMapped;
			m_queueLatency.add(std::chrono::duration<double, std::milli>(
								   std::chrono::steady_clock::now() - item.arrived)
								   .count());
		}
	}
	else if (auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservation>(item.object))
	{
		if (std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(obs))
			++m_counts.odometry;
		else
			++m_counts.otherObservations;
		processOther(obs);
	}
	else
		++m_counts.notObservations;
	reportWarnings();
}

void CLiveProcessor::reportWarnings()
{
	for (const auto& w : takeWarnings())
	{
		++m_warningsTotal;
		if (m_warningsShown++ < kMaxWarningsShown)
			message("warning: " + w);
		else if (m_warningsShown == kMaxWarningsShown + 1)
			message("warning: further warnings are counted in stats.json, not shown");
	}
}

}  // namespace lrgc::apps
