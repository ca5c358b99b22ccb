#include "live/SensorRig.h"

#include "CommandLine.h"

#include <mrpt/config/CConfigFile.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/hwdrivers/registerAllClasses.h>
#include <mrpt/system/COutputLogger.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <mutex>
#include <sstream>

namespace lrgc::apps
{
namespace
{
// rawlog-grabber's [global] keys (MRPT 2.5): accepted and not used.
const std::vector<std::string> kGrabberGlobalKeys = {
	"rawlog_prefix",     "time_between_launches", "SF_max_time_span",
	"use_sensoryframes", "GRABBER_PERIOD_MS",     "rawlog_GZ_compress_level"};

TSensorSection checkSection(const mrpt::config::CConfigFileBase& ini, const std::string& path,
							const std::string& section)
{
	const auto where = path + ": [" + section + "]";
	TSensorSection s;
	s.section = section;
	s.driver = ini.read_string(section, "driver", "");
	if (s.driver.empty())
		throw CSetupError(where +
						  ": no `driver` key (every section but [global] is a sensor, as for "
						  "rawlog-grabber)");
	const auto sensor = createDriver(s.driver);
	if (!sensor)
		throw CSetupError(where + ": driver '" + s.driver +
						  "' is not a sensor class of mrpt::hwdrivers (for example CLMS100Eth, "
						  "CSickLaserSerial, CSickLaserUSB, CHokuyoURG, CRoboPeakLidar)");
	silenceDriverConsole(*sensor);
	try
	{
		sensor->loadConfig(ini, section);
	}
	catch (const std::exception& e)
	{
		throw CSetupError(where + " (" + s.driver + "): " + oneLineError(e));
	}
	s.label = sensor->getSensorLabel();
	s.processRate = sensor->getProcessRate();
	if (!(s.processRate > 0))
		throw CSetupError(where + ": process_rate must be set to a rate > 0 [Hz]");
	return s;
}
}  // namespace

mrpt::hwdrivers::CGenericSensor::Ptr createDriver(const std::string& driver)
{
	static std::once_flag registered;
	std::call_once(registered, [] { mrpt::hwdrivers::registerAllClasses_mrpt_hwdrivers(); });
	return mrpt::hwdrivers::CGenericSensor::createSensorPtr(driver);
}

void silenceDriverConsole(mrpt::hwdrivers::CGenericSensor& sensor)
{
	auto* log = dynamic_cast<mrpt::system::COutputLogger*>(&sensor);
	if (!log) return;
	log->logging_enable_console_output = false;
	log->setMinLoggingLevel(mrpt::system::LVL_WARN);
	log->setVerbosityLevelForCallbacks(mrpt::system::LVL_WARN);
}

void routeDriverLog(mrpt::hwdrivers::CGenericSensor& sensor,
					std::function<void(const std::string&)> sink)
{
	auto* log = dynamic_cast<mrpt::system::COutputLogger*>(&sensor);
	if (!log) return;
	silenceDriverConsole(sensor);
	log->logRegisterCallback(
		[sink = std::move(sink)](std::string_view msg, const mrpt::system::VerbosityLevel,
								 std::string_view, const mrpt::Clock::time_point)
		{ sink(oneLineText(std::string(msg))); });
}

TSensorRig loadSensorRig(const std::string& iniPath)
{
	if (!std::filesystem::is_regular_file(iniPath))
		throw CSetupError("sensors file '" + iniPath + "' does not exist");
	const mrpt::config::CConfigFile ini(iniPath);
	TSensorRig rig;
	rig.iniPath = iniPath;
	std::vector<std::string> sections;
	ini.getAllSections(sections);
	for (const auto& section : sections)
	{
		if (section.empty()) continue;
		if (section == "global")
		{
			std::vector<std::string> keys, unknown;
			ini.getAllKeys(section, keys);
			for (const auto& k : keys)
				if (std::find(kGrabberGlobalKeys.begin(), kGrabberGlobalKeys.end(), k) ==
					kGrabberGlobalKeys.end())
					unknown.push_back(k);
			if (!keys.empty())
				rig.notes.push_back(
					iniPath +
					": [global] is rawlog-grabber's section; lrgc-slam does not use it (the "
					"capture goes to DIR/capture.rawlog)");
			for (const auto& k : unknown)
				rig.notes.push_back(iniPath + ": [global] " + k +
									": not a rawlog-grabber key (misspelt?)");
			continue;
		}
		rig.sensors.push_back(checkSection(ini, iniPath, section));
	}
	if (rig.sensors.empty())
		throw CSetupError(iniPath + ": no sensor section (a section with a `driver` key)");
	return rig;
}

}  // namespace lrgc::apps
