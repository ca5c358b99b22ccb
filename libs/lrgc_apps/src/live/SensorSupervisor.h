/* CSensorSupervisor: one live sensor in its own thread, kept alive whatever it does.
 *
 * The thread runs the driver as rawlog-grabber does (create by class name, loadConfig from the
 * .ini section, initialize(), then doProcess() + getObservations() at the section's
 * process_rate) and hands every observation to the sink (CLiveQueues::push). Observations
 * that carry no data (a range scan with fewer than 2 rays: what CLMS100Eth returns once its
 * connection is gone) are counted as rejected, not handed over.
 *
 * Start. A sensor has started when it delivers its first valid observation, not when its
 * initialize() returns: some drivers return from it without a device (CLMS100Eth with nothing
 * at its address). One that delivers nothing within sensor_timeout_s of initialize() is
 * reported as "cannot start: no valid data within ..." and retried like a failed start.
 *
 * Failures. A driver that cannot start (initialize() throws: no device, connection refused),
 * throws in doProcess(), or delivers no valid observation for [LiveMapping] sensor_timeout_s
 * (disconnected, sending garbage, stuck in an error state) is reported with what it said,
 * destroyed (which closes its port or socket) and created again after a back-off that doubles
 * from retry_initial_s up to retry_max_s; once data flows again the back-off is reset and the
 * recovery is reported. Each sensor has its own thread, so one failing sensor never holds up
 * the others. requestStop() is seen between driver calls: a driver blocked inside a call (e.g.
 * CLMS100Eth's start-up, which sleeps 10 s) is waited for by join().
 */
#pragma once

#include "LiveMappingParams.h"
#include "live/SensorRig.h"
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/serialization/CSerializable.h>

#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

namespace lrgc::apps
{
/** A snapshot of one sensor's counters. */
struct TSensorCounters
{
	size_t starts = 0;        //!< (re)starts that delivered valid data
	size_t failures = 0;      //!< failed starts, driver errors and data time-outs
	size_t observations = 0;  //!< objects handed to the sink
	size_t scans = 0;         //!< of which 2D laser scans
	size_t rejected = 0;      //!< objects without data (scans with < 2 rays), not handed over
	/** "starting" (until its first valid data), "ok", "retrying", "stopped", or "blocked N s"
	 * while a doProcess() call has lasted longer than sensor_timeout_s (a driver stuck in a
	 * call cannot be interrupted). */
	std::string state = "starting";
	std::string lastProblem;  //!< the last failure as reported, empty if none
};

class CSensorSupervisor
{
public:
	/** Returns false when the intake is closed. */
	using TSink = std::function<bool(const mrpt::serialization::CSerializable::Ptr&)>;
	using TReport = std::function<void(const std::string& line, bool important)>;

	/** `ini` must outlive the supervisor. */
	CSensorSupervisor(const mrpt::config::CConfigFileBase& ini, TSensorSection sensor,
					  const TLiveMappingParams& params, TSink sink, TReport report);
	~CSensorSupervisor();
	CSensorSupervisor(const CSensorSupervisor&) = delete;
	CSensorSupervisor& operator=(const CSensorSupervisor&) = delete;

	void start();
	void requestStop();
	void join();

	const TSensorSection& sensor() const { return m_sensor; }
	TSensorCounters counters() const;

private:
	using TClock = std::chrono::steady_clock;
	void threadMain();
	mrpt::hwdrivers::CGenericSensor::Ptr startDriver();
	/** The first valid data since the driver's (re)start: it has started. */
	void noteDataFlowing(const mrpt::hwdrivers::CGenericSensor& driver, TClock::time_point now);
	/** Runs the driver until stop (nullopt) or a failure (its description). */
	std::optional<std::string> runDriver(mrpt::hwdrivers::CGenericSensor& driver);
	void handOver(const mrpt::hwdrivers::CGenericSensor::TListObservations& objects,
				  size_t& valid);
	/** Waits `seconds` or until stop; false if stopped. */
	bool waitFor(double seconds);
	void waitUntil(TClock::time_point t);
	bool stopping() const;
	void fail(const std::string& what, bool starting);
	void setState(const std::string& state);
	void setInCall(bool inCall);
	std::string name() const;
	std::string takeDriverMessage();

	const mrpt::config::CConfigFileBase& m_ini;
	const TSensorSection m_sensor;
	const TLiveMappingParams m_params;
	TSink m_sink;
	TReport m_report;
	std::thread m_thread;

	mutable std::mutex m_mutex;
	std::condition_variable m_stopCv;
	bool m_stop = false;
	TSensorCounters m_counters;
	std::string m_driverMessage;  //!< last warning/error the driver logged
	size_t m_driverMessages = 0;

	double m_backoff;                                 //!< [s] next wait before a restart
	std::optional<TClock::time_point> m_inCallSince;  //!< inside doProcess() since
	bool m_flowing = false;                           //!< valid data since the last (re)start
	std::optional<TClock::time_point> m_outageSince;  //!< data stopped or never came
};

}  // namespace lrgc::apps
