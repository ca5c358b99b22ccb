/* lrgc-slam runs an icp-slam .ini as it is: MRPT's own icp-slam_demo_classic.ini (Debian
 * mrpt-common), its rawlog_file pointed at SENA, maps with exit status 0 into its
 * logOutput_dir (relative to the current folder, as for icp-slam), writing lrgc's outputs and
 * icp-slam's names; icp-slam's own settings are reported once as ignored. */
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/serialization/CArchive.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "app_runner.h"
#include "test_data.h"

namespace fs = std::filesystem;
using namespace lrgc::test;

namespace
{
const char* kDemoIni = "/usr/share/mrpt/config_files/icp-slam/icp-slam_demo_classic.ini";

// The demo .ini with rawlog_file and rawlog_offset replaced.
std::string demoIni(const std::string& rawlog, size_t offset)
{
	std::istringstream in(readTextFile(kDemoIni));
	std::string out;
	for (std::string line; std::getline(in, line);)
	{
		if (line.rfind("rawlog_file", 0) == 0) line = "rawlog_file=" + rawlog;
		if (line.rfind("rawlog_offset", 0) == 0)
			line = "rawlog_offset=" + std::to_string(offset);
		out += line + "\n";
	}
	return out;
}

size_t count(const std::string& text, const std::string& what)
{
	size_t n = 0;
	for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1))
		++n;
	return n;
}

mrpt::maps::CSimpleMap loadSimplemap(const std::string& path)
{
	mrpt::maps::CSimpleMap map;
	mrpt::io::CFileGZInputStream f(path);
	mrpt::serialization::archiveFrom(f) >> map;
	return map;
}

struct TPathLine
{
	size_t step = 0;
	double x = 0, y = 0, phi = 0;
};

std::vector<TPathLine> readPath(const std::string& path)
{
	std::ifstream f(path);
	std::vector<TPathLine> out;
	TPathLine l;
	while (f >> l.step >> l.x >> l.y >> l.phi) out.push_back(l);
	return out;
}
}  // namespace

TEST(IcpSlamIni, MrptsDemoIniRunsAndWritesBothOutputSets)
{
	LRGC_SKIP_IF_MISSING(senaRawlogPath());
	LRGC_SKIP_IF_MISSING(kDemoIni);
	const std::string dir = makeTempDir("icp_slam_ini_" + std::to_string(::getpid()));
	writeTextFile(dir + "/icp.ini", demoIni(senaRawlogPath(), 0));
	const auto r = runProcess(binaryPath("lrgc-slam"), {"icp.ini", "--quiet"}, dir);
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_EQ(count(r.output, "ignored"), 1u) << r.output;  // reported once, not refused
	EXPECT_NE(r.output.find("sections [ICP]"), std::string::npos) << r.output;
	EXPECT_NE(r.output.find("insertionLinDistance"), std::string::npos) << r.output;

	const std::string out = dir + "/LOG_ICP-SLAM";  // the demo's logOutput_dir
	for (const char* name : {"map.gridmap.gz", "map.simplemap.gz", "trajectory.tum",
							 "stats.json", "_finalmap_.simplemap", "log_estimated_path.txt"})
		EXPECT_TRUE(fileExists(out + "/" + name)) << name;
	EXPECT_EQ(loadSimplemap(out + "/_finalmap_.simplemap").size(),
			  loadSimplemap(out + "/map.simplemap.gz").size());
	// icp-slam's format: "step x y phi", one line per log entry (SENA: 225), the last one at
	// our last pose.
	const auto path = readPath(out + "/log_estimated_path.txt");
	ASSERT_EQ(path.size(), 225u);
	EXPECT_EQ(path.front().step, 0u);
	EXPECT_EQ(path.back().step, 224u);
	std::istringstream tum(readTextFile(out + "/trajectory.tum"));
	double t, x, y, z, qx, qy, qz, qw;
	while (tum >> t >> x >> y >> z >> qx >> qy >> qz >> qw)
	{
	}
	EXPECT_NEAR(path.back().x, x, 1e-5);
	EXPECT_NEAR(path.back().y, y, 1e-5);
	EXPECT_NEAR(path.back().phi, 2 * std::atan2(qz, qw), 1e-5);
}

TEST(IcpSlamIni, RawlogOffsetSkipsEntriesAndTheSecondArgumentIsTheRawlog)
{
	LRGC_SKIP_IF_MISSING(senaRawlogPath());
	LRGC_SKIP_IF_MISSING(kDemoIni);
	const std::string dir = makeTempDir("icp_slam_offset_" + std::to_string(::getpid()));
	// rawlog_file names a missing file: the second argument replaces it, as in icp-slam.
	writeTextFile(dir + "/icp.ini", demoIni(dir + "/missing.rawlog", 100));
	const auto r =
		runProcess(binaryPath("lrgc-slam"), {"icp.ini", senaRawlogPath(), "--quiet"}, dir);
	ASSERT_EQ(r.exitCode, 0) << r.output;
	// As icp-slam counts: SENA is a sensory frame, then action/frame pairs, so entry j ends at
	// object 1 + 2 j, and entries 50 (object 101) to 224 are mapped.
	const auto path = readPath(dir + "/LOG_ICP-SLAM/log_estimated_path.txt");
	ASSERT_EQ(path.size(), 175u);
	EXPECT_EQ(path.front().step, 50u);
	EXPECT_EQ(path.back().step, 224u);
	EXPECT_NE(readTextFile(dir + "/LOG_ICP-SLAM/stats.json").find("\"scans\": 175,"),
			  std::string::npos);
}

TEST(IcpSlamIni, MissingKeysAndOtherFilesAreClearErrors)
{
	const std::string dir = makeTempDir("icp_slam_bad_" + std::to_string(::getpid()));
	writeTextFile(dir + "/no-out.ini", "[MappingApplication]\nrawlog_file = x.rawlog\n");
	auto r = runProcess(binaryPath("lrgc-slam"), {"no-out.ini"}, dir);
	EXPECT_EQ(r.exitCode, 2) << r.output;
	EXPECT_NE(r.output.find("no-out.ini: [MappingApplication] logOutput_dir is missing"),
			  std::string::npos)
		<< r.output;
	writeTextFile(
		dir + "/offset.ini",
		"[MappingApplication]\nrawlog_file = x\nlogOutput_dir = o\nrawlog_offset = -3\n");
	r = runProcess(binaryPath("lrgc-slam"), {"offset.ini"}, dir);
	EXPECT_EQ(r.exitCode, 2) << r.output;
	EXPECT_NE(r.output.find("offset.ini:4: [MappingApplication] rawlog_offset '-3'"),
			  std::string::npos)
		<< r.output;
	writeTextFile(dir + "/lrgc.ini", "[MapBuilder]\nkeyframe_distance_m = 0.3\n");
	r = runProcess(binaryPath("lrgc-slam"), {"lrgc.ini"}, dir);
	EXPECT_EQ(r.exitCode, 2) << r.output;
	EXPECT_NE(r.output.find("not an option, nor an icp-slam .ini"), std::string::npos)
		<< r.output;
	r = runProcess(binaryPath("lrgc-slam"), {"offset.ini", "--out", "x"}, dir);
	EXPECT_EQ(r.exitCode, 2) << r.output;
	EXPECT_NE(r.output.find("which takes no --out"), std::string::npos) << r.output;
}
