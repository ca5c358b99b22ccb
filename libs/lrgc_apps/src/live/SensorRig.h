/* The live sensors: a rawlog-grabber .ini read as rawlog-grabber reads it.
 *
 * Every section but [global] is one sensor, run in its own thread by the mrpt::hwdrivers class
 * named by its `driver` key (CSickLaserSerial, CLMS100Eth, CSickLaserUSB, CHokuyoURG, ..., and
 * whatever odometry source the robot has as a CGenericSensor); the other keys of the section
 * are the driver's own (process_rate, sensorLabel, pose_*, ports, ...), passed to it unchanged
 * by CGenericSensor::loadConfig. [global] holds rawlog-grabber's own settings (rawlog_prefix,
 * ...): lrgc-slam does not need them (its capture is DIR/capture.rawlog) and says so.
 * loadSensorRig() creates and configures each driver once, without starting it, so that an
 * unknown driver, a missing key or a bad process_rate is a usage error before anything runs.
 */
#pragma once

#include "ErrorText.h"
#include <mrpt/hwdrivers/CGenericSensor.h>

#include <functional>
#include <string>
#include <vector>

namespace lrgc::apps
{
struct TSensorSection
{
	std::string section;     //!< .ini section name
	std::string driver;      //!< CGenericSensor class name
	std::string label;       //!< sensorLabel after loadConfig (names the observations)
	double processRate = 0;  //!< [Hz] doProcess() rate, from the section
};

struct TSensorRig
{
	std::string iniPath;
	std::vector<TSensorSection> sensors;
	std::vector<std::string> notes;  //!< things the user should know (ignored keys, ...)
};

/** Reads `iniPath`; throws CUsageError naming the file, section and problem. */
TSensorRig loadSensorRig(const std::string& iniPath);

/** A new driver of class `driver` (MRPT's drivers registered first); nullptr if unknown. */
mrpt::hwdrivers::CGenericSensor::Ptr createDriver(const std::string& driver);

/** Sends the driver's log messages (if it is an mrpt::system::COutputLogger) of level warning
 * and above to `sink` instead of the console: some drivers (CLMS100Eth) turn debug output on in
 * their constructor and would flood stdout. */
void routeDriverLog(mrpt::hwdrivers::CGenericSensor& sensor,
					std::function<void(const std::string&)> sink);
/** Only the console part of routeDriverLog(): console output off, level warning. */
void silenceDriverConsole(mrpt::hwdrivers::CGenericSensor& sensor);

}  // namespace lrgc::apps
