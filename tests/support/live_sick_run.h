/* Shared by the live tests against the LMS1xx emulator (live_sick_test.cpp,
 * live_sick_saved_map_test.cpp): the run's folder with its sensors and lrgc .ini files, and
 * readers of what a run writes. */
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <string>
#include <vector>

#include "lms1xx_emulator.h"

namespace lrgc::test
{
constexpr double kLiveStartupBound = 150;  // [s] upper bound for CLMS100Eth's ~15 s start-up

struct TLiveRunDirs
{
	std::string dir, sensors, config, out;
};

/** A fresh folder with sensors.ini (one CLMS100Eth on the emulator's port at `sensorPose`)
 * and lrgc.ini ([LiveMapping] with short status and retry intervals, then `extraKeys`). */
TLiveRunDirs prepareLiveRun(const std::string& name, const CLms1xxEmulator& emu,
							const mrpt::poses::CPose3D& sensorPose,
							const std::string& extraKeys);

/** Value of an integer JSON key (first occurrence after `after`); -1 if absent. */
long jsonInt(const std::string& json, const std::string& key, const std::string& after = {});

/** The rows of a TUM file (stamp x y z qx qy qz qw). */
std::vector<std::vector<double>> readTum(const std::string& path);

}  // namespace lrgc::test
