/* CLiveSlam::run and lrgc-slam --live: the checks before a live run, then one CLiveSession
 * (LiveSession.h: the threads, stop sequence, saves and live.json). */
#include "live/LiveSlam.h"

#include "SlamApp.h"
#include "live/LiveSession.h"
#include "StopSignalWatcher.h"

#include <csignal>
#include <filesystem>

namespace lrgc::apps
{
int CLiveSlam::run(const std::function<bool()>& stop)
{
	const TSensorRig rig = loadSensorRig(m_setup.sensorsIni);
	std::filesystem::create_directories(m_setup.outDir);
	const auto capturePath = std::filesystem::path(m_setup.outDir) / "capture.rawlog";
	if (std::filesystem::exists(capturePath))
		throw CUsageError(
			"'" + capturePath.string() +
			"' exists: a live run never overwrites a capture; choose another --out DIR or move "
			"the file");
	// A socket driver writing to a peer that went away must get EPIPE, not kill the process.
	const auto oldSigpipe = std::signal(SIGPIPE, SIG_IGN);
	int exitCode;
	{
		CLiveSession session(m_setup, rig, m_err, m_periodicSaveHook);
		session.mapUntilStopped(stop);
		exitCode = session.finish();
	}
	std::signal(SIGPIPE, oldSigpipe);
	return exitCode;
}

int runLiveSlam(const TSlamCommandLine& cl, std::FILE* err)
{
	TLiveSlamSetup setup;
	setup.sensorsIni = cl.live;
	setup.config = loadAppConfig(cl);
	for (const auto& w : setup.config.warnings)  // keys read under an old name
		std::fprintf(err, "warning: %s\n", w.c_str());
	setup.outDir = cl.outDir;
	setup.quiet = cl.quiet;
	if (!cl.initialMap.empty()) setup.initialMap = loadSavedMap(cl.initialMap, "--initial-map");
	if (!cl.localize.empty()) setup.localizeMap = loadSavedMap(cl.localize, "--localize");
	for (const auto* map : {&setup.initialMap, &setup.localizeMap})
		if (*map)
			for (const auto& w : (*map)->warnings)
				std::fprintf(err, "warning: %s\n", w.c_str());
	const CStopSignalWatcher signals;  // before the run's threads, which inherit its mask
	setup.cut = signals.token();
	return CLiveSlam(std::move(setup), err).run([&] { return signals.stopRequested(); });
}

}  // namespace lrgc::apps
