/* CLiveLocalizer: a live run with --localize MAP: the robot is localised on a saved map by the
 * same CLocalizer as `--input FILE --localize MAP` (global localisation for the start and after
 * a loss beside tracking, on its search thread), and the map is never changed. Its outputs are
 * those of the offline run (trajectory.tum, timing.csv, stats.json, config.ini:
 * LocalizationOutputs.h), saved periodically and at the end, each atomically; poses and timing
 * rows are streamed, so memory stays flat over hours. Events (started, lost, kidnapped,
 * relocalised) are said on the console as they come.
 *
 * One difference with a log: a global search's result is applied at the first scan after it
 * ended ([LiveMapping] loop_results_when_ready, default true), never making tracking wait;
 * false applies it at the scan the modelled search time fixes, as offline.
 */
#pragma once

#include <lrgc/localization/Localizer.h>
#include <lrgc_apps/RunOutputs.h>
#include <lrgc_apps/RunStats.h>
#include "LocalizationOutputs.h"
#include "live/LiveProcessor.h"

#include <memory>
#include <string>

namespace lrgc::apps
{
struct TSavedMap;

class CLiveLocalizer final : public CLiveProcessor
{
public:
	CLiveLocalizer(const TAppConfig& config, const TSavedMap& map, const std::string& outDir,
				   std::string sensorsIni, CLiveConsole& console);

	void finish() override {}  // the map is not changed: nothing to optimise
	std::string failure() const override;
	bool anyScan() const override { return m_localizer->stats().scans > 0; }
	std::function<std::string()> saveJob(const std::string& status) override;
	std::string statusText(size_t queueDepth) const override;
	std::string summaryText() const override;
	void setStopToken(const CStopToken& stop) override { m_localizer->setStopToken(stop); }

	const CLocalizer& localizer() const { return *m_localizer; }

private:
	void processScan(const mrpt::obs::CObservation2DRangeScan::Ptr& scan) override;
	void processOther(const mrpt::obs::CObservation::Ptr& obs) override;
	std::vector<std::string> takeWarnings() override { return {}; }
	/** Says the localiser's events since the last call. */
	void reportEvents();

	std::string m_mapPath;
	std::unique_ptr<CLocalizer> m_localizer;
	CLocalizationRecorder m_recorder;
	TRunSummary m_run;
	CRunClock m_clock;
	size_t m_eventsSaid = 0;
};

}  // namespace lrgc::apps
