/* lrgc-slam --live SENSORS.ini --out DIR: mapping from live mrpt::hwdrivers sensors, with
 * nothing lost.
 *
 * Threads. One per sensor (CSensorSupervisor: the driver loop of rawlog-grabber, plus
 * restarts with back-off), one capture writer (CCaptureWriter: DIR/capture.rawlog, each object
 * on disk as it arrives), the calling thread, which maps (CLiveMapper: the offline map
 * builder) and prints the status line, and a saver (CLiveSaver) that writes the saves. The
 * sensors hand every observation to CLiveQueues, which gives the writer and the mapper the
 * same objects in the same order; the queues are unbounded, so acquisition never waits for
 * disk or mapping.
 *
 * Falling behind. The mapper skips laser scans by CKeepUpPolicy ([LiveMapping]
 * max_backlog_scans) and says so; the capture is never thinned.
 *
 * Saving. Every output of an offline run (maps, trajectory, graph, stats.json, timing.csv) is
 * written atomically every [LiveMapping] save_interval_s and at the end, with live.json
 * (per-sensor counts, restarts, capture size, queue latency). For a periodic save the mapping
 * thread only takes a snapshot between two scans; the saver thread builds the grid
 * (incrementally) and writes, so mapping never waits for the disk. A stop (the first Ctrl-C
 * or SIGTERM, or `stop()` returning true) closes the intake, maps what is queued, waits for a
 * periodic save still running, runs the final optimisation and saves; a second signal exits
 * at once (_exit in the handler): the capture is whole objects and the last saved maps are
 * whole files, so both stay valid.
 */
#pragma once

#include "AppConfig.h"
#include "CommandLine.h"
#include "lrgc_apps/SavedMap.h"

#include <lrgc/common/StopToken.h>

#include <cstdio>
#include <functional>
#include <optional>
#include <string>

namespace lrgc::apps
{
struct TLiveSlamSetup
{
	std::string sensorsIni;  //!< rawlog-grabber .ini of the sensors
	TAppConfig config;       //!< lrgc parameters, [LiveMapping] included
	std::string outDir;
	bool quiet = false;
	/** --initial-map (continue it) or --localize (localise on it): at most one is set. */
	std::optional<TSavedMap> initialMap, localizeMap;
	/** Stopped by the first signal. Three seconds later, if the stop is not over, the
	 * computation in hand (a loop search, an optimisation, a scan match, a global search) and
	 * those of the scans still queued end early, as in an offline run (DelayedStop.h); a
	 * map's end of run (revisit sweep, final optimisation) then runs whole (a second signal
	 * exits at once). */
	CStopToken cut;
};

/** Called at the start of every periodic save (tests only: LiveSlamTestAccess.h). */
using TPeriodicSaveHook = std::function<void(const std::function<size_t()>& scansMapped)>;
struct TLiveSlamTestAccess;

class CLiveSlam
{
public:
	CLiveSlam(TLiveSlamSetup setup, std::FILE* err) : m_setup(std::move(setup)), m_err(err) {}

	/** Maps until `stop()` returns true (polled about 10 times a second) or a fatal error.
	 * Returns kExitOk after a stop with everything saved, kExitInputError if mapping or the
	 * capture failed (what was mapped is saved). Throws CUsageError, before anything starts,
	 * for a bad sensors file or an existing DIR/capture.rawlog (never overwritten). */
	int run(const std::function<bool()>& stop);

private:
	friend struct TLiveSlamTestAccess;  // tests: a slow periodic save
	TLiveSlamSetup m_setup;
	std::FILE* m_err;
	TPeriodicSaveHook m_periodicSaveHook;  //!< empty but in tests
};

/** CSlamApp's live runner: loads the configuration and runs CLiveSlam until SIGINT or SIGTERM
 * (taken by a CStopSignalWatcher; a second one exits at once with status 130). */
int runLiveSlam(const TSlamCommandLine& cl, std::FILE* err);

}  // namespace lrgc::apps
