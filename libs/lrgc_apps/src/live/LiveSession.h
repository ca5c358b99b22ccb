/* CLiveSession: one live run (CLiveSlam::run): the sensors' threads, the capture writer, the
 * saver, the mapping loop on the calling thread and the stop sequence (LiveSlam.h tells the
 * whole story). */
#pragma once

#include "live/CaptureWriter.h"
#include "live/DelayedStop.h"
#include "live/LiveConsole.h"
#include "live/LiveJson.h"
#include "live/LiveProcessor.h"
#include "live/LiveQueues.h"
#include "live/LiveSaver.h"
#include "live/LiveSlam.h"
#include "live/SensorRig.h"
#include "live/SensorSupervisor.h"

#include <mrpt/config/CConfigFile.h>

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace lrgc::apps
{
using TSensors = std::vector<std::unique_ptr<CSensorSupervisor>>;

/** The first fatal error of the run (capture or mapping), set from any thread. */
class CFatal
{
public:
	void set(const std::string& why)
	{
		std::lock_guard<std::mutex> lock(m_mutex);
		if (m_why.empty()) m_why = why;
		m_set = true;
	}
	bool isSet() const { return m_set; }
	std::string why() const
	{
		std::lock_guard<std::mutex> lock(m_mutex);
		return m_why;
	}

private:
	mutable std::mutex m_mutex;
	std::atomic<bool> m_set{false};
	std::string m_why;
};

/** One live run: its threads and the stop sequence. */
class CLiveSession
{
public:
	CLiveSession(const TLiveSlamSetup& setup, const TSensorRig& rig, std::FILE* err,
				 TPeriodicSaveHook saveHook);

	~CLiveSession();

	/** Maps until stop() or a fatal error, then maps what is queued. */
	void mapUntilStopped(const std::function<bool()>& stop);

	/** Closes the capture, final optimisation and save, waits for the drivers; exit status. */
	int finish();

private:
	/** "no sensor delivered data: <each one's last problem>" if none ever started (delivered
	 * a valid observation), else empty: the run then ends with exit status 1. */
	std::string noSensorStarted() const;

	static std::string captureFileOf(const std::string& outDir);

	void beginStop();

	void mapItem(const TLiveItem& item, size_t behind);

	/** Hands a save to the saver thread: the mapping thread only takes the snapshots (poses,
	 * counters, shared scans) and goes on mapping; false if the last save still runs (the
	 * caller tries again after the next item). */
	bool periodicSave();

	/** Writes a save: every output (the processor's job), then live.json; returns what was
	 * saved. On the saver thread, or on this one once it is idle. */
	std::string writeSave(const std::function<std::string()>& job, TLiveJsonState live);

	TLiveJsonState liveState(const std::string& status) const;

	void writeLiveJson(const TLiveJsonState& st);

	void writeLiveJson(const std::string& status);

	void summary(const std::string& status);

	const TLiveSlamSetup& m_setup;
	const TPeriodicSaveHook m_saveHook;  //!< tests only (LiveSlamTestAccess.h)
	const TLiveMappingParams& m_params;
	CCaptureWriter m_capture;
	const mrpt::config::CConfigFile m_ini;  //!< read by the sensor threads
	CLiveConsole m_console;
	CLiveQueues m_queues;
	CDelayedStop m_cut;  //!< setup.cut, kCutGraceSeconds later
	std::unique_ptr<CLiveProcessor> m_processor;
	CFatal m_fatal;
	bool m_mappingFailed = false;
	std::thread m_writer;
	std::atomic<size_t> m_scansMapped{0};  //!< for the tests' save hook
	size_t m_saves = 0;  //!< saves written (by the saver thread, then by finish())
	CLiveSaver m_saver;  //!< after what its jobs use: stopped (and its job done) before them
	TSensors m_sensors;  //!< last: destroyed (stopped and joined) first
};
}  // namespace lrgc::apps
