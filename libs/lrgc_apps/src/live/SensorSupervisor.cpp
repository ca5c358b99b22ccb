#include "live/SensorSupervisor.h"

#include <mrpt/core/format.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <algorithm>

namespace lrgc::apps
{
namespace
{
/** An object with no data in it: nothing to capture or map. */
bool carriesNoData(const mrpt::serialization::CSerializable::Ptr& obj)
{
	if (!obj) return true;
	const auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obj);
	return scan && scan->getScanSize() < 2;
}
}  // namespace

CSensorSupervisor::CSensorSupervisor(const mrpt::config::CConfigFileBase& ini,
									 TSensorSection sensor, const TLiveMappingParams& params,
									 TSink sink, TReport report)
	: m_ini(ini),
	  m_sensor(std::move(sensor)),
	  m_params(params),
	  m_sink(std::move(sink)),
	  m_report(std::move(report)),
	  m_backoff(params.retry_initial_s)
{
}

CSensorSupervisor::~CSensorSupervisor()
{
	requestStop();
	join();
}

void CSensorSupervisor::start()
{
	m_thread = std::thread([this] { threadMain(); });
}

void CSensorSupervisor::requestStop()
{
	{
		std::lock_guard<std::mutex> lock(m_mutex);
		m_stop = true;
	}
	m_stopCv.notify_all();
}

void CSensorSupervisor::join()
{
	if (m_thread.joinable()) m_thread.join();
}

TSensorCounters CSensorSupervisor::counters() const
{
	std::lock_guard<std::mutex> lock(m_mutex);
	TSensorCounters c = m_counters;
	if (m_inCallSince)
	{
		const double inCall =
			std::chrono::duration<double>(TClock::now() - *m_inCallSince).count();
		if (inCall > m_params.sensor_timeout_s)
			c.state = mrpt::format("blocked %.0f s", inCall);
	}
	return c;
}

bool CSensorSupervisor::stopping() const
{
	std::lock_guard<std::mutex> lock(m_mutex);
	return m_stop;
}

bool CSensorSupervisor::waitFor(double seconds)
{
	std::unique_lock<std::mutex> lock(m_mutex);
	return !m_stopCv.wait_for(lock, std::chrono::duration<double>(seconds),
							  [&] { return m_stop; });
}

void CSensorSupervisor::waitUntil(TClock::time_point t)
{
	std::unique_lock<std::mutex> lock(m_mutex);
	m_stopCv.wait_until(lock, t, [&] { return m_stop; });
}

void CSensorSupervisor::setInCall(bool inCall)
{
	std::lock_guard<std::mutex> lock(m_mutex);
	if (inCall)
		m_inCallSince = TClock::now();
	else
		m_inCallSince.reset();
}

void CSensorSupervisor::setState(const std::string& state)
{
	std::lock_guard<std::mutex> lock(m_mutex);
	m_counters.state = state;
}

std::string CSensorSupervisor::name() const
{
	return "[" + m_sensor.section + "] " + m_sensor.driver;
}

std::string CSensorSupervisor::takeDriverMessage()
{
	std::lock_guard<std::mutex> lock(m_mutex);
	std::string m;
	if (m_driverMessages == 1)
		m = "driver said: '" + m_driverMessage + "'";
	else if (m_driverMessages > 1)
		m = mrpt::format("driver said %zu times, last: '%s'", m_driverMessages,
						 m_driverMessage.c_str());
	m_driverMessages = 0;
	m_driverMessage.clear();
	return m;
}

void CSensorSupervisor::threadMain()
{
	while (!stopping())
	{
		setState("starting");
		mrpt::hwdrivers::CGenericSensor::Ptr driver;
		try
		{
			driver = startDriver();
		}
		catch (const std::exception& e)
		{
			fail("cannot start: " + oneLineError(e), true);
			if (!waitFor(m_backoff)) break;
			m_backoff = std::min(2 * m_backoff, m_params.retry_max_s);
			continue;
		}
		if (!driver) break;  // stop requested during start-up
		const std::optional<std::string> failure = runDriver(*driver);
		driver.reset();  // closes the device before any wait
		if (!failure) break;
		fail(*failure, !m_flowing);  // no data since initialize(): it has not started
		if (!waitFor(m_backoff)) break;
		m_backoff = std::min(2 * m_backoff, m_params.retry_max_s);
	}
	setState("stopped");
}

void CSensorSupervisor::fail(const std::string& what, bool starting)
{
	const std::string said = takeDriverMessage();
	const std::string line =
		mrpt::format("live: %s %s%s; %s in %.3g s", name().c_str(), what.c_str(),
					 said.empty() ? "" : (" (" + said + ")").c_str(),
					 starting ? "retrying" : "restarting it", m_backoff);
	{
		std::lock_guard<std::mutex> lock(m_mutex);
		++m_counters.failures;
		m_counters.lastProblem = line;
		m_counters.state = "retrying";
	}
	if (!m_outageSince) m_outageSince = TClock::now();
	m_flowing = false;
	m_report(line, true);
}

mrpt::hwdrivers::CGenericSensor::Ptr CSensorSupervisor::startDriver()
{
	auto driver = createDriver(m_sensor.driver);
	if (!driver) THROW_EXCEPTION_FMT("unknown driver class '%s'", m_sensor.driver.c_str());
	routeDriverLog(*driver,
				   [this](const std::string& msg)
				   {
					   std::lock_guard<std::mutex> lock(m_mutex);
					   m_driverMessage = msg;
					   ++m_driverMessages;
				   });
	driver->loadConfig(m_ini, m_sensor.section);
	silenceDriverConsole(*driver);  // in case loadConfig changed the logging level
	if (stopping()) return nullptr;
	// Started only once it delivers (runDriver): a driver whose initialize() returns without
	// a device (CLMS100Eth with nothing at its address) would otherwise show as "ok".
	driver->initialize();
	return driver;
}

void CSensorSupervisor::noteDataFlowing(const mrpt::hwdrivers::CGenericSensor& driver,
										TClock::time_point now)
{
	m_flowing = true;
	m_backoff = m_params.retry_initial_s;
	{
		std::lock_guard<std::mutex> lock(m_mutex);
		++m_counters.starts;
		m_counters.state = "ok";
	}
	m_report(mrpt::format("live: %s started (label '%s', %.0f Hz)", name().c_str(),
						  driver.getSensorLabel().c_str(), driver.getProcessRate()),
			 false);
	if (m_outageSince)
		m_report(mrpt::format("live: %s data again after %.1f s without; mapping resumes",
							  name().c_str(),
							  std::chrono::duration<double>(now - *m_outageSince).count()),
				 true);
	m_outageSince.reset();
}

void CSensorSupervisor::handOver(
	const mrpt::hwdrivers::CGenericSensor::TListObservations& objects, size_t& valid)
{
	for (const auto& [stamp, obj] : objects)
	{
		if (carriesNoData(obj))
		{
			std::lock_guard<std::mutex> lock(m_mutex);
			++m_counters.rejected;
			continue;
		}
		if (!m_sink(obj)) return;  // intake closed: the run is stopping
		++valid;
		std::lock_guard<std::mutex> lock(m_mutex);
		++m_counters.observations;
		m_counters.scans +=
			std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obj) != nullptr;
	}
}

std::optional<std::string> CSensorSupervisor::runDriver(mrpt::hwdrivers::CGenericSensor& driver)
{
	const auto period = std::chrono::duration_cast<TClock::duration>(
		std::chrono::duration<double>(1.0 / m_sensor.processRate));
	TClock::time_point lastValid = TClock::now();
	size_t rejectedSinceValid = 0;
	while (!stopping())
	{
		const TClock::time_point t0 = TClock::now();
		mrpt::hwdrivers::CGenericSensor::TListObservations objects;
		try
		{
			setInCall(true);
			driver.doProcess();
			setInCall(false);
			driver.getObservations(objects);
		}
		catch (const std::exception& e)
		{
			setInCall(false);
			return "failed: " + oneLineError(e);
		}
		size_t valid = 0;
		handOver(objects, valid);
		rejectedSinceValid += objects.size() - valid;
		const TClock::time_point now = TClock::now();
		if (valid > 0)
		{
			lastValid = now;
			rejectedSinceValid = 0;
			if (!m_flowing) noteDataFlowing(driver, now);
		}
		else if (std::chrono::duration<double>(now - lastValid).count() >
				 m_params.sensor_timeout_s)
		{
			std::string detail = driver.getState() == mrpt::hwdrivers::CGenericSensor::ssError
									 ? "driver in error state"
									 : "driver working";
			if (rejectedSinceValid > 0)
				detail += mrpt::format(", %zu observation(s) without data", rejectedSinceValid);
			if (!m_outageSince) m_outageSince = lastValid;
			if (!m_flowing)  // the grace period after initialize() is over
				return mrpt::format(
					"cannot start: no valid data within %.1f s of its start (%s)",
					m_params.sensor_timeout_s, detail.c_str());
			return mrpt::format("sent no valid data for %.1f s: %s", m_params.sensor_timeout_s,
								detail.c_str());
		}
		waitUntil(t0 + period);
	}
	return std::nullopt;
}

}  // namespace lrgc::apps
