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
 * --initial-map: the builder starts with the saved map, and the live scans' start in it is
 * found as offline (CSlamApp::startInInitialMap): the first scans go to a CStartFinder's probe
 * and are kept; each new probe keyframe may bring a global correlation (on this thread: the
 * sensors' observations wait in the queue meanwhile, none is lost); once it passes, the
 * session starts there and the kept observations are mapped.
 */
#pragma once

#include <lrgc/localization/GlobalLocalizer.h>
#include <lrgc/localization/StartFinder.h>
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
	/** --initial-map, start not yet found: the observation to the probe; tries to locate. */
	void seekStart(const mrpt::obs::CObservation::Ptr& obs);
	/** Writes a save's outputs (the grid brought up to date incrementally). */
	void writeSave(const TRunOutputsSnapshot& outputs);

	CMetricMapBuilderLRGC m_builder;
	std::string m_outDir;
	TRunSummary m_run;
	CRunClock m_clock;
	CStopToken m_stop;
	// --initial-map, until the start is found:
	std::unique_ptr<CGlobalLocalizer> m_global;
	std::unique_ptr<CStartFinder> m_finder;
	std::vector<mrpt::obs::CObservation::Ptr> m_kept;  //!< mapped once the start is found
	std::unique_ptr<CIncrementalGrid> m_grid;  //!< the saves' grid (saver thread, then final)
};

}  // namespace lrgc::apps
