/* CLiveMapper (see LiveMapper.h). */
#include "live/LiveMapper.h"

#include "PieceReports.h"
#include "RunConfigFile.h"
#include "lrgc_apps/SavedMap.h"

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
	message("live: " + continuingMessage(*initialMap, m_builder, m_run), false);
	m_joiner = std::make_unique<CPieceJoiner>(m_builder.graph(), m_builder.keyframes(),
											  config.lrgc.correlator, config.localization);
	m_joiner->setResultsWhenReady(config.live.loop_results_when_ready);
	m_builder.freezeMap();
	m_builder.startPiece();
}

CLiveMapper::~CLiveMapper() = default;

void CLiveMapper::setStopToken(const CStopToken& stop)
{
	m_stop = stop;
	m_builder.setStopToken(stop);
	if (m_joiner) m_joiner->setStopToken(stop);
}

void CLiveMapper::processScan(const mrpt::obs::CObservation2DRangeScan::Ptr& scan)
{
	mapScan(scan);
	joinIfFound();
}

void CLiveMapper::processOther(const mrpt::obs::CObservation::Ptr& obs)
{
	m_builder.processObservation(obs);
	joinIfFound();
}

// After each observation, as offline after each log entry, at the newest scan's time.
void CLiveMapper::joinIfFound()
{
	if (!m_joiner || !m_builder.pieceFirstNode()) return;
	const std::optional<TPieceJoin> join =
		m_joiner->service(m_builder, mrpt::Clock::toDouble(m_builder.lastScanTimestamp()));
	if (!join) return;
	m_builder.joinPiece(join->node, join->nodeInMap, join->cov);
	message("live: " + joinMessage(*join, *m_joiner, m_builder, m_run), false);
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
	if (!m_joiner) return;
	recordJoinerFigures(*m_joiner, m_builder, m_run);
	const std::string kept = keptPieceMessage(m_builder, m_run);
	if (!kept.empty()) message("live: " + kept, false);
}

// A session never joined to its initial map is kept (keptPieceMessage), as offline.
std::string CLiveMapper::failure() const
{
	return {};
}

TRunOutputsSnapshot CLiveMapper::snapshot(const std::string& status) const
{
	TRunSummary run = m_run;
	if (m_joiner) recordJoinerFigures(*m_joiner, m_builder, run);
	if (m_joiner && !run.joined && run.frame.empty()) run.frame = pieceFrame(m_builder);
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
	const std::string text =
		mrpt::format("mapped %zu, queue %zu, loop closures %zu", counts().scansMapped,
					 queueDepth, m_builder.stats().loopClosures);
	if (!m_joiner || !m_builder.pieceFirstNode()) return text;
	return text + mrpt::format(", mapping as a piece not yet joined (%zu attempts)",
							   m_joiner->attempts());
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
