/* CLiveMapper: the mapping side of a live run. It owns the same map builder as an offline run
 * (CMetricMapBuilderLRGC, fed with processObservation() exactly as an observations-only rawlog
 * is fed offline) and takes the snapshots of every output that the live saver writes
 * (CLiveSaver), periodically and at the end.
 *
 * Same map as a replay. Scans are prepared as the offline reader prepares them
 * (CLiveProcessor), so when no scan was skipped and no stop cut a computation short,
 * `lrgc-slam --input DIR/capture.rawlog` feeds the builder the same observations in the same
 * order and gives the same trajectory and maps.
 *
 * --initial-map: as offline (CSlamApp::continueInitialMap), the builder starts with the saved
 * map frozen and maps every scan at once, from the first, as a piece of its own
 * (CMetricMapBuilderLRGC::startPiece); after each observation a CPieceJoiner is serviced: it
 * correlates the piece's recent patch against the saved map on its worker thread and, once a
 * correlation passes the filters, the piece is joined to the map (joinPiece). Live, a search's
 * result is taken as soon as it is ready ([LiveMapping] loop_results_when_ready), never making
 * mapping wait; with that off it is taken at the scan the modelled search time fixes, as
 * offline, so the map equals the offline app's on the capture. A session never joined is
 * kept and saved in its own frame (stats.json: joined false, frame), as offline.
 */
#pragma once

#include <lrgc/localization/PieceJoiner.h>
#include <lrgc/map_builder/CMetricMapBuilderLRGC.h>
#include <lrgc/map_builder/IncrementalGrid.h>
#include <lrgc_apps/RunOutputs.h>
#include <lrgc_apps/RunStats.h>
#include "live/LiveProcessor.h"

#include <memory>
#include <string>
#include <vector>

namespace lrgc::apps
{
struct TSavedMap;

class CLiveMapper final : public CLiveProcessor
{
public:
	/** `initialMap`: continue it (see the file comment), or nullptr for a new map. */
	CLiveMapper(const TAppConfig& config, std::string outDir, std::string sensorsIni,
				CLiveConsole& console, const TSavedMap* initialMap = nullptr);
	~CLiveMapper() override;

	void finish() override;
	std::string failure() const override;
	bool anyScan() const override { return m_builder.stats().scans > 0; }
	std::function<std::string()> saveJob(const std::string& status) override;
	std::string statusText(size_t queueDepth) const override;
	std::string summaryText() const override;
	void setStopToken(const CStopToken& stop) override;

	/** Every output as of now, with `status` in stats.json (writeRunOutputs). */
	TRunOutputsSnapshot snapshot(const std::string& status) const;
	const CMetricMapBuilderLRGC& builder() const { return m_builder; }
	const std::string& outDir() const { return m_outDir; }

private:
	void processScan(const mrpt::obs::CObservation2DRangeScan::Ptr& scan) override;
	void processOther(const mrpt::obs::CObservation::Ptr& obs) override;
	std::vector<std::string> takeWarnings() override { return m_builder.takeWarnings(); }
	void mapScan(const mrpt::obs::CObservation2DRangeScan::Ptr& scan);
	/** --initial-map, the piece not yet joined: services the joiner, joins on a find. */
	void joinIfFound();
	/** Writes a save's outputs (the grid brought up to date incrementally). */
	void writeSave(const TRunOutputsSnapshot& outputs);

	CMetricMapBuilderLRGC m_builder;
	std::string m_outDir;
	TRunSummary m_run;
	CRunClock m_clock;
	CStopToken m_stop;
	std::unique_ptr<CPieceJoiner> m_joiner;    //!< --initial-map
	std::unique_ptr<CIncrementalGrid> m_grid;  //!< the saves' grid (saver thread, then final)
};

}  // namespace lrgc::apps
