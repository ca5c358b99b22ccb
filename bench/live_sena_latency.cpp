/* Live latency on SENA by hand: the scenario of tests/live_sick_test.cpp (lrgc-slam --live with
 * MRPT's CLMS100Eth driver reading Debian's SENA rawlog from the LMS1xx emulator on 127.0.0.1),
 * with periodic saves, printing the latencies the run reports: live.json's queue latency
 * (arrival to mapped) and stats.json's per-scan mapping latency, median / p99 / max [ms], and
 * the periodic saves' durations. Each run takes about 25 s, most of it CLMS100Eth's start-up.
 *
 * Run: build/bin/live_sena_latency [--slam BIN] [--save-interval S] [--runs N] [--keep DIR]
 *   --slam           the lrgc-slam to run (default: this build's)
 *   --save-interval  [LiveMapping] save_interval_s (default 1)
 *   --runs           runs, one after the other (default 1)
 *   --keep           write the runs' folders under DIR (default: a temporary folder)
 * Every scan is mapped (max_backlog_scans = 0), so a slow scan shows as queue latency instead
 * of skipped scans; loop-closing results are applied when ready (the live default).
 */
#include <mrpt/core/bits_math.h>

#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <regex>
#include <sstream>

#include "app_runner.h"
#include "child_process.h"
#include "lms1xx_emulator.h"
#include "test_data.h"

namespace fs = std::filesystem;
using namespace lrgc::test;

namespace
{
/** The three numbers after "KEY": {"median": a, "p99": b, "max": c (first occurrence). */
std::string summary(const std::string& json, const std::string& key)
{
	std::smatch m;
	const std::regex re("\"" + key +
						"\": \\{\"median\": ([0-9.]+), \"p99\": ([0-9.]+), \"max\": ([0-9.]+)");
	if (!std::regex_search(json, m, re)) return "(absent)";
	return "median " + std::string(m[1]) + ", p99 " + std::string(m[2]) + ", max " +
		   std::string(m[3]);
}

long jsonInt(const std::string& json, const std::string& key)
{
	std::smatch m;
	if (!std::regex_search(json, m, std::regex("\"" + key + "\": (-?[0-9]+)"))) return -1;
	return std::stol(m[1]);
}

/** The durations of "live: maps saved (...) in X s" lines. */
std::string saveDurations(const std::string& log)
{
	std::string out;
	const std::regex re("live: maps saved \\([^)]*\\) in ([0-9.]+) s");
	for (auto it = std::sregex_iterator(log.begin(), log.end(), re);
		 it != std::sregex_iterator(); ++it)
		out += (out.empty() ? "" : " ") + std::string((*it)[1]);
	return out.empty() ? "none" : out;
}

int runOnce(const TLms1xxRecording& rec, const std::string& slam, double saveInterval,
			const std::string& dir)
{
	CLms1xxEmulator emu(rec.scans);
	fs::create_directories(dir);
	const std::string sensors = dir + "/sensors.ini", config = dir + "/lrgc.ini",
					  out = dir + "/out";
	std::ostringstream s;
	s << "[LASER]\ndriver = CLMS100Eth\nprocess_rate = 50\nsensorLabel = LMS1XX\n"
	  << "ip_address = 127.0.0.1\nTCP_port = " << emu.port()
	  << "\npose_x = " << rec.sensorPose.x() << "\npose_y = " << rec.sensorPose.y()
	  << "\npose_z = " << rec.sensorPose.z()
	  << "\npose_yaw = " << mrpt::RAD2DEG(rec.sensorPose.yaw())
	  << "\npose_pitch = 0\npose_roll = 0\n";
	writeTextFile(sensors, s.str());
	writeTextFile(config,
				  "[LiveMapping]\nstatus_interval_s = 0.5\nsensor_timeout_s = 2\n"
				  "max_backlog_scans = 0\nsave_interval_s = " +
					  std::to_string(saveInterval) + "\n");
	CChildProcess app(slam, {"--live", sensors, "--config", config, "--out", out},
					  dir + "/live.log");
	// Served to the end, or lrgc-slam gave up early (a bad --keep folder, a crash).
	waitUntil([&] { return emu.finished() || app.waitExit(0).has_value(); }, 300);
	if (!emu.finished() || !app.waitForOutput("sent no valid data", 60))
	{
		std::fprintf(stderr, "the live run did not get through SENA; its output:\n%s\n",
					 app.output().c_str());
		return 1;
	}
	app.signal(SIGTERM);
	const auto rc = app.waitExit(120);
	if (!rc || *rc != 0)
	{
		std::fprintf(stderr, "lrgc-slam --live ended with %d:\n%s\n", rc ? *rc : -1,
					 app.output().c_str());
		return 1;
	}
	const std::string live = readTextFile(out + "/live.json"),
					  stats = readTextFile(out + "/stats.json");
	std::printf(
		"scans served %zu, mapped %ld, skipped %ld, periodic saves %ld (took [s]: %s)\n"
		"  queue latency [ms]: %s\n  mapping latency [ms]: %s\n",
		emu.scansServed(), jsonInt(live, "scans_mapped"), jsonInt(live, "skipped_to_keep_up"),
		jsonInt(live, "saves"), saveDurations(app.output()).c_str(),
		summary(live, "queue_latency_ms").c_str(), summary(stats, "latency_ms").c_str());
	std::fflush(stdout);
	return 0;
}
}  // namespace

int main(int argc, char** argv)
{
	std::string slam = binaryPath("lrgc-slam"), keep;
	double saveInterval = 1;
	int runs = 1;
	for (int i = 1; i + 1 < argc; i += 2)
	{
		const std::string a = argv[i], v = argv[i + 1];
		if (a == "--slam")
			slam = v;
		else if (a == "--save-interval")
			saveInterval = std::atof(v.c_str());
		else if (a == "--runs")
			runs = std::atoi(v.c_str());
		else if (a == "--keep")
			keep = v;
		else
		{
			std::fprintf(stderr, "unknown option '%s'\n", a.c_str());
			return 2;
		}
	}
	if (!fileExists(senaRawlogPath()))
	{
		std::fprintf(stderr, "SENA rawlog not installed: %s\n", senaRawlogPath().c_str());
		return 1;
	}
	const TLms1xxRecording rec = lms1xxScansFromRawlog(senaRawlogPath());
	const std::string base =
		keep.empty() ? makeTempDir("live_sena_latency_" + std::to_string(::getpid())) : keep;
	std::printf("%s, SENA through the LMS1xx emulator (%zu scans), save_interval_s %g\n",
				slam.c_str(), rec.scans.size(), saveInterval);
	for (int r = 0; r < runs; ++r)
	{
		std::printf("run %d: ", r + 1);
		if (runOnce(rec, slam, saveInterval, base + "/run" + std::to_string(r + 1)) != 0)
			return 1;
	}
	return 0;
}
