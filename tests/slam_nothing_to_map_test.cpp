/* End to end: a log that holds nothing lrgc can map (no 2D laser scan, only unusable scans,
 * only malformed CARMEN lines) ends with exit status 1 and a line saying what the log holds;
 * no empty map is written (an empty trajectory and a blank grid would pass for a map), and
 * stats.json has the counts. Malformed CARMEN lines are reported wherever they are, the last
 * lines of the file included. */
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>

#include "app_runner.h"
#include "test_data.h"

namespace fs = std::filesystem;
using namespace lrgc::test;

namespace
{
void expectStatsOnly(const std::string& out)
{
	for (const char* name : {"map.gridmap.gz", "map.png", "map.pgm", "map.yaml",
							 "map.simplemap.gz", "trajectory.tum", "graph.graph", "timing.csv"})
		EXPECT_FALSE(fs::exists(out + "/" + name))
			<< name << " written for a run without a map";
	EXPECT_TRUE(fs::exists(out + "/stats.json"));
}

// A CARMEN FLASER line: 180 readings of `range` [m], robot and laser at the origin.
std::string flaserLine(double range, double stamp)
{
	std::ostringstream line;
	line << "FLASER 180";
	for (int i = 0; i < 180; ++i) line << ' ' << range;
	line << " 0 0 0 0 0 0 " << stamp << " host " << stamp << '\n';
	return line.str();
}

size_t countOf(const std::string& text, const std::string& what)
{
	size_t n = 0;
	for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1))
		++n;
	return n;
}
}  // namespace

TEST(SlamNothingToMap, ALogWithoutLaserScansSaysWhatItHolds)
{
	const std::string log = "/usr/share/mrpt/datasets/kf-slam_demo.rawlog";  // mrpt-common
	LRGC_SKIP_IF_MISSING(log);
	const std::string out = makeTempDir("nothing_no_laser") + "/out";
	const auto r =
		runProcess(binaryPath("lrgc-slam"), {"--input", log, "--out", out, "--quiet"});
	EXPECT_EQ(r.exitCode, 1) << r.output;
	EXPECT_NE(r.output.find("nothing to map: '" + log +
							"' holds no 2D laser scan (CObservation2DRangeScan); it holds 250 "
							"CActionRobotMovement2D, 250 CObservationBearingRange"),
			  std::string::npos)
		<< r.output;
	EXPECT_EQ(r.output.find("complete"), std::string::npos) << r.output;
	expectStatsOnly(out);
	const std::string stats = readTextFile(out + "/stats.json");
	EXPECT_NE(stats.find("\"status\": \"nothing to map: "), std::string::npos) << stats;
	EXPECT_NE(stats.find("\"CObservationBearingRange\": 250"), std::string::npos) << stats;
	EXPECT_NE(stats.find("\"scans\": 0,"), std::string::npos) << stats;
}

TEST(SlamNothingToMap, ScansWithoutEnoughReturnsAreNoMap)
{
	const std::string dir = makeTempDir("nothing_no_returns");
	writeTextFile(dir + "/blind.clf", flaserLine(0, 1) + flaserLine(0, 2) + flaserLine(0, 3));
	const auto r = runProcess(binaryPath("lrgc-slam"), {"--input", dir + "/blind.clf", "--out",
														dir + "/out", "--quiet"});
	EXPECT_EQ(r.exitCode, 1) << r.output;
	EXPECT_NE(r.output.find("nothing to map: none of the 3 2D laser scans of '" + dir +
							"/blind.clf' could be mapped (3 with fewer valid returns than "
							"[MapBuilder] min_scan_points = 20)"),
			  std::string::npos)
		<< r.output;
	expectStatsOnly(dir + "/out");
}

TEST(SlamNothingToMap, AFileOfMalformedLinesFailsListingAFewOfThem)
{
	const std::string dir = makeTempDir("nothing_malformed");
	std::string text;
	for (int i = 0; i < 12; ++i) text += "FLASER 180 1 2 3\n";
	writeTextFile(dir + "/bad.clf", text);
	const auto r = runProcess(binaryPath("lrgc-slam"),
							  {"--input", dir + "/bad.clf", "--out", dir + "/out", "--quiet"});
	EXPECT_EQ(r.exitCode, 1) << r.output;
	EXPECT_NE(r.output.find(dir + "/bad.clf: line 1: malformed"), std::string::npos)
		<< r.output;
	EXPECT_EQ(countOf(r.output, ": malformed"), 5u) << "listed, then counted: " << r.output;
	EXPECT_NE(r.output.find("7 more malformed lines not listed (12 in all)"), std::string::npos)
		<< r.output;
	EXPECT_NE(r.output.find("holds no 2D laser scan (CObservation2DRangeScan); it holds 12 "
							"malformed FLASER lines"),
			  std::string::npos)
		<< r.output;
	expectStatsOnly(dir + "/out");
	const std::string stats = readTextFile(dir + "/out/stats.json");
	EXPECT_NE(stats.find("\"malformed_lines\": 12,"), std::string::npos) << stats;
}

TEST(SlamNothingToMap, MalformedLastLinesAreReportedAndCounted)
{
	// Warnings used to be shown only when a good line followed: these two were never shown.
	const std::string dir = makeTempDir("malformed_at_end");
	writeTextFile(dir + "/log.clf", flaserLine(2.0, 1) + "FLASER 180 1 2 3\nODOM 1 2\n");
	const auto r = runProcess(binaryPath("lrgc-slam"),
							  {"--input", dir + "/log.clf", "--out", dir + "/out", "--quiet"});
	EXPECT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find(dir + "/log.clf: line 2: malformed"), std::string::npos)
		<< r.output;
	EXPECT_NE(r.output.find(dir + "/log.clf: line 3: malformed"), std::string::npos)
		<< r.output;
	const std::string stats = readTextFile(dir + "/out/stats.json");
	EXPECT_NE(stats.find("\"status\": \"complete\""), std::string::npos) << stats;
	EXPECT_NE(stats.find("\"malformed_lines\": 2,"), std::string::npos) << stats;
	EXPECT_TRUE(fs::exists(dir + "/out/map.gridmap.gz"));
}
