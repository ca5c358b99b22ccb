/* CLiveLocalizer (see LiveLocalizer.h). */
#include "live/LiveLocalizer.h"

#include "RunConfigFile.h"
#include "lrgc_apps/SavedMap.h"

#include <mrpt/core/format.h>

#include <chrono>

namespace lrgc::apps
{
CLiveLocalizer::CLiveLocalizer(const TAppConfig& config, const TSavedMap& map,
							   const std::string& outDir, std::string sensorsIni,
							   CLiveConsole& console)
	: CLiveProcessor(config, console, "localisation"),
	  m_mapPath(map.path),
	  m_localizer(localizerOnSavedMap(map, config)),
	  m_recorder(outDir)
{
	m_localizer->setResultsWhenReady(config.live.loop_results_when_ready);
	m_run.input = std::move(sensorsIni);
	m_run.format = "live";
	m_run.configIni = runConfigText(config, m_run.input);
	message(mrpt::format("live: localising on '%s' (the map is not changed); finding the start",
						 m_mapPath.c_str()),
			false);
}

void CLiveLocalizer::processScan(const mrpt::obs::CObservation2DRangeScan::Ptr& scan)
{
	const size_t scansBefore = m_localizer->stats().scans;
	const auto t0 = std::chrono::steady_clock::now();
	const double cpu0 = threadCpuMs();
	m_localizer->processObservation(scan);
	if (m_localizer->stats().scans > scansBefore)
	{
		TScanTiming t;
		t.replayWaitMs = 1e3 * m_localizer->lastReplayWaitSeconds();
		t.latencyMs =
			std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
				.count() -
			t.replayWaitMs;
		t.cpuMs = threadCpuMs() - cpu0;
		t.stamp = mrpt::Clock::toDouble(scan->timestamp);
		m_recorder.addScan(t, *m_localizer);
	}
	reportEvents();
}

void CLiveLocalizer::processOther(const mrpt::obs::CObservation::Ptr& obs)
{
	m_localizer->processObservation(obs);
}

void CLiveLocalizer::reportEvents()
{
	const auto& events = m_localizer->stats().events;
	for (; m_eventsSaid < events.size(); ++m_eventsSaid)
		message(localizationEventLine(events[m_eventsSaid]),
				events[m_eventsSaid].kind != TLocalizationEvent::Kind::Started);
}

std::string CLiveLocalizer::failure() const
{
	const TLocalizerStats& s = m_localizer->stats();
	if (s.started) return {};
	return noStartMessage(m_mapPath, s.scans, s.globalAttempts, s.lastRejection);
}

std::function<std::string()> CLiveLocalizer::saveJob(const std::string& status)
{
	TRunSummary run = m_run;
	run.status = status;
	run.logEntries = counts().items;
	finishRunSummary(run, m_clock, warnings());
	auto save = std::make_shared<const TLocalizationSave>(
		m_recorder.snapshot(*m_localizer, std::move(run), m_mapPath));
	const TLocalizerStats& s = m_localizer->stats();
	const std::string what =
		mrpt::format("poses saved (%zu scans, %zu localised)", s.scans, s.localizedScans);
	return [save, what]
	{
		writeLocalizationSave(*save);
		return what;
	};
}

std::string CLiveLocalizer::statusText(size_t queueDepth) const
{
	const TLocalizerStats& s = m_localizer->stats();
	return mrpt::format("localised %zu of %zu, queue %zu, lost %zu, relocalised %zu",
						s.localizedScans, s.scans, queueDepth, s.lostEvents, s.relocalizations);
}

std::string CLiveLocalizer::summaryText() const
{
	const TLocalizerStats& s = m_localizer->stats();
	return mrpt::format(
		"%zu of %zu scans localised on '%s' (start after %zu scans, lost %zu times, %zu "
		"relocalisations), %zu skipped to keep up",
		s.localizedScans, s.scans, m_mapPath.c_str(), s.scansBeforeStart, s.lostEvents,
		s.relocalizations, policy().skippedTotal());
}

}  // namespace lrgc::apps
