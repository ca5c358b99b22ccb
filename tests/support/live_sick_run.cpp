#include "live_sick_run.h"

#include <mrpt/core/bits_math.h>

#include <unistd.h>

#include <fstream>
#include <regex>
#include <sstream>

#include "app_runner.h"
#include "test_data.h"

namespace lrgc::test
{
TLiveRunDirs prepareLiveRun(const std::string& name, const CLms1xxEmulator& emu,
							const mrpt::poses::CPose3D& sensorPose,
							const std::string& extraKeys)
{
	TLiveRunDirs d;
	d.dir = makeTempDir(name + "_" + std::to_string(::getpid()));
	d.sensors = d.dir + "/sensors.ini";
	d.config = d.dir + "/lrgc.ini";
	d.out = d.dir + "/out";
	std::ostringstream s;
	s << "# rawlog-grabber style: [global] plus one section per sensor\n"
	  << "[global]\nrawlog_prefix = ./dataset\ntime_between_launches = 300\n"
	  << "SF_max_time_span = 0.005\nuse_sensoryframes = 0\n\n"
	  << "[LASER]\ndriver = CLMS100Eth\nprocess_rate = 50\nsensorLabel = LMS1XX\n"
	  << "ip_address = 127.0.0.1\nTCP_port = " << emu.port() << "\n"
	  << "pose_x = " << sensorPose.x() << "\npose_y = " << sensorPose.y()
	  << "\npose_z = " << sensorPose.z() << "\npose_yaw = " << mrpt::RAD2DEG(sensorPose.yaw())
	  << "\npose_pitch = 0\npose_roll = 0\n";
	writeTextFile(d.sensors, s.str());
	writeTextFile(d.config,
				  "[LiveMapping]\nstatus_interval_s = 0.5\nsensor_timeout_s = 2\n"
				  "retry_initial_s = 0.5\nretry_max_s = 2\n" +
					  extraKeys);
	return d;
}

long jsonInt(const std::string& json, const std::string& key, const std::string& after)
{
	const size_t from = after.empty() ? 0 : json.find(after);
	const std::regex re("\"" + key + "\": (-?[0-9]+)");
	std::smatch m;
	const std::string tail = json.substr(from == std::string::npos ? 0 : from);
	if (!std::regex_search(tail, m, re)) return -1;
	return std::stol(m[1]);
}

std::vector<std::vector<double>> readTum(const std::string& path)
{
	std::vector<std::vector<double>> rows;
	std::ifstream f(path);
	for (std::string line; std::getline(f, line);)
	{
		if (line.empty() || line[0] == '#') continue;
		std::istringstream in(line);
		std::vector<double> v;
		for (double x; in >> x;) v.push_back(x);
		rows.push_back(v);
	}
	return rows;
}

}  // namespace lrgc::test
