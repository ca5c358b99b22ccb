/* CLiveMapper (see LiveMapper.h). */
#include "live/LiveMapper.h"

#include "LocalizationOutputs.h"
#include "RunConfigFile.h"
#include "lrgc_apps/SavedMap.h"

#include <lrgc/common/se2.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/core/format.h>

#include <chrono>
#include <filesystem>

namespace lrgc::apps
{
namespace
{
/** A live run takes loop-closing results as [LiveMapping] loop_results_when_ready says. */
lrgc::TLRGCParams liveParams(const TAppConfig& config)
{
	lrgc::TLRGCParams p = config.lrgc;
	p.loop.apply_when_ready = config.live.loop_results_when_ready;
	return p;
}
}  // namespace

CLiveMapper::CLiveMapper(const TAppConfig& config, std::string outDir, std::string sensorsIni,
						 CLiveConsole& console, const TSavedMap* initialMap)
	: CLiveProcessor(config, console, "mapping"),
	  m_builder(liveParams(config)),
	  m_outDir(std::move(outDir))
{
	m_builder.logging_enable_console_output = false;  // warnings are reported by the base
	m_run.input = std::move(sensorsIni);
	m_run.format = "live";
	m_run.configIni = runConfigText(config, m_run.input);
	m_run.mrptRawlog = (std::filesystem::path(m_outDir) / "capture.rawlog").string();
	if (!initialMap) return;
	initializeFromSavedMap(m_builder, *initialMap);
	m_run.initialMap = initialMap->path;
	m_run.initialMapKeyframes = m_builder.graph().numNodes();
	m_global = std::make_unique<CGlobalLocalizer>(m_builder.graph(), m_builder.keyframes(),
												  config.lrgc.correlator);
	m_finder = std::make_unique<CStartFinder>(*m_global, config.lrgc, config.localization);
	message(mrpt::format("live: continuing '%s': %zu keyframes, %zu links; finding where the "
						 "scans start in it",
						 initialMap->path.c_str(), m_builder.graph().numNodes(),
						 m_builder.graph().numLinks()),
			false);
}

CLiveMapper::~CLiveMapper() = default;

void CLiveMapper::setStopToken(const CStopToken& stop)
{
	m_stop = stop;
	m_builder.setStopToken(stop);
	if (m_global) m_global->setStopToken(stop);
	if (m_finder) m_finder->setStopToken(stop);
}

void CLiveMapper::processScan(const mrpt::obs::CObservation2DRangeScan::Ptr& scan)
{
	if (m_finder)
		seekStart(scan);
	else
		mapScan(scan);
}

void CLiveMapper::processOther(const mrpt::obs::CObservation::Ptr& obs)
{
	if (m_finder)
		seekStart(obs);
	else
		m_builder.processObservation(obs);
}

void CLiveMapper::seekStart(const mrpt::obs::CObservation::Ptr& obs)
{
	m_finder->probe().processObservation(obs);
	m_kept.push_back(obs);
	const std::optional<TStartFound> found = m_finder->tryLocate();
	if (!found) return;
	const TPose2D start =
		compose(found->probeInMap, m_finder->probe().trajectory().front().robotInMap);
	m_run.startScans = m_finder->probe().stats().scans;
	m_run.startAttempts = m_finder->attempts();
	m_run.startSeconds = m_finder->secondsSpent();
	message(mrpt::format("live: the scans start at (%.2f m, %.2f m, %.1f deg) in the map: "
						 "found after %zu scans, %zu attempts, %.1f s (score %.2f)",
						 start.x, start.y, mrpt::RAD2DEG(start.phi), m_run.startScans,
						 m_run.startAttempts, m_run.startSeconds, found->score),
			false);
	m_builder.startSessionAt(start, found->cov);
	m_finder.reset();
	m_global.reset();
	for (const auto& kept : std::exchange(m_kept, {}))
		if (auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(kept))
			mapScan(scan);
		else
			m_builder.processObservation(kept);
}

void CLiveMapper::mapScan(const mrpt::obs::CObservation2DRangeScan::Ptr& scan)
{
	const size_t scansBefore = m_builder.stats().scans;
	const auto t0 = std::chrono::steady_clock::now();
	m_builder.processObservation(scan);
	if (m_builder.stats().scans > scansBefore)
	{
		m_run.latencyMs.push_back(
			std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
				.count());
		m_run.latencyStamp.push_back(mrpt::Clock::toDouble(scan->timestamp));
	}
}

void CLiveMapper::finish()
{
	// The first signal cut the computation in hand (TLiveSlamSetup::cut); the end of the run
	// (loop results due, revisit sweep, final optimisation) runs whole, as a stop asks.
	m_builder.setStopToken({});
	const auto t0 = std::chrono::steady_clock::now();
	m_builder.finish();
	m_run.finalOptimizationSeconds =
		std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string CLiveMapper::failure() const
{
	if (!m_finder) return {};
	return noStartMessage(m_run.initialMap, m_finder->probe().stats().scans,
						  m_finder->attempts(), m_finder->lastRejection());
}

TRunOutputsSnapshot CLiveMapper::snapshot(const std::string& status) const
{
	TRunSummary run = m_run;
	run.status = status;
	run.logEntries = counts().items;
	finishRunSummary(run, m_clock, warnings());
	return snapshotRunOutputs(m_builder, std::move(run));
}

std::function<std::string()> CLiveMapper::saveJob(const std::string& status)
{
	auto outputs = std::make_shared<const TRunOutputsSnapshot>(snapshot(status));
	return [this, outputs]
	{
		writeSave(*outputs);
		return mrpt::format("maps saved (%zu scans, %zu keyframes)", outputs->stats.scans,
							outputs->stats.keyframes);
	};
}

void CLiveMapper::writeSave(const TRunOutputsSnapshot& outputs)
{
	const TGridSettings& gs = outputs.gridSettings;
	if (!m_grid || m_grid->settings().resolution != gs.resolution ||
		m_grid->settings().settleKeyframes != gs.settleKeyframes)
		m_grid = std::make_unique<CIncrementalGrid>(gs);
	if (outputs.stats.scans > 0) m_grid->update(outputs.gridKeyframes);
	writeRunOutputs(outputs, *m_grid->grid(), m_outDir);
}

std::string CLiveMapper::statusText(size_t queueDepth) const
{
	if (m_finder)
		return mrpt::format("finding the start in the map (%zu scans, %zu attempts), queue %zu",
							m_finder->probe().stats().scans, m_finder->attempts(), queueDepth);
	return mrpt::format("mapped %zu, queue %zu, loop closures %zu", counts().scansMapped,
						queueDepth, m_builder.stats().loopClosures);
}

std::string CLiveMapper::summaryText() const
{
	const auto& st = m_builder.stats();
	return mrpt::format(
		"%zu mapped, %zu skipped to keep up, %zu keyframes, %zu loop closures (%zu loop links)",
		counts().scansMapped, policy().skippedTotal(), st.keyframes, st.loopClosures,
		st.loopClosureLinks);
}

}  // namespace lrgc::apps
