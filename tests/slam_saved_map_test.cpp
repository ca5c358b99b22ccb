/* lrgc-slam --initial-map and --localize as a user runs them, on the SENA rawlog (Debian's
 * mrpt-common): on an lrgc output folder, on MRPT's own icp-slam simplemap, and with bad
 * arguments (one-line errors, exit statuses of the README). */
#include <gtest/gtest.h>
#include <lrgc_apps/io/PoseGraphText.h>

#include <fstream>
#include <unistd.h>

#include "app_runner.h"
#include "mirrored_sena.h"
#include "test_data.h"

using namespace lrgc::test;

namespace
{
const std::string kIcpSlam = "/usr/bin/icp-slam";

size_t graphNodes(const std::string& folder)
{
	std::ifstream in(folder + "/graph.lrgc");
	return lrgc::poseGraphFromText(in, folder + "/graph.lrgc").graph.numNodes();
}

std::string field(const std::string& json, const std::string& key)
{
	const auto p = json.find("\"" + key + "\": ");
	if (p == std::string::npos) return {};
	const auto b = p + key.size() + 4;
	return json.substr(b, json.find_first_of(",}\n", b) - b);
}
}  // namespace

// A start must fit scan by scan, not only the correlation's grid (CLocalizer::probeMatchesMap,
// and CPieceJoiner's scan check for a continued map). Without that check, the mirrored scans'
// patch passed the paper's filters after 149 scans (a corridor is a corridor in a mirror), and
// tracking then matched no scan well: kidnapped five scans later, and every scan reported
// localised.
TEST(SlamSavedMap, senaSeenInAMirrorFindsNoStartAndJoinsNot)
{
	LRGC_SKIP_IF_MISSING(senaRawlogPath());
	const std::string dir = makeTempDir("slam_mirror_" + std::to_string(::getpid()));
	const auto map = runProcess(binaryPath("lrgc-slam"), {"--input", senaRawlogPath(), "--out",
														  dir + "/map", "--quiet"});
	ASSERT_EQ(map.exitCode, 0) << map.output;
	writeMirroredSena(dir + "/mirror.rawlog");
	// The mirrored log on SENA's map: `mode` --localize or --initial-map, outputs in dir/out.
	const auto onTheMap = [&](const std::string& mode, const std::string& out)
	{
		return runProcess(binaryPath("lrgc-slam"),
						  {"--input", dir + "/mirror.rawlog", mode, dir + "/map", "--out",
						   dir + "/" + out, "--quiet"});
	};
	const auto loc = onTheMap("--localize", "loc");
	EXPECT_EQ(loc.exitCode, 1) << loc.output;
	EXPECT_NE(loc.output.find("no start found"), std::string::npos) << loc.output;
	const std::string stats = readTextFile(dir + "/loc/stats.json");
	EXPECT_EQ(field(stats, "kidnapped"), "0") << stats;
	EXPECT_NE(field(stats, "refused_by_scan_check"), "0") << stats;

	// Continued as a piece: joined by the grid alone before the check (38 % of its scan
	// matched), now kept apart.
	const auto cont = onTheMap("--initial-map", "cont");
	ASSERT_EQ(cont.exitCode, 0) << cont.output;
	EXPECT_NE(cont.output.find("was not joined"), std::string::npos) << cont.output;
	const std::string contStats = readTextFile(dir + "/cont/stats.json");
	EXPECT_NE(contStats.find("\"joined\": false"), std::string::npos) << contStats;
}

TEST(SlamSavedMap, senaContinuedAndLocalisedOnItsOwnMap)
{
	LRGC_SKIP_IF_MISSING(senaRawlogPath());
	const std::string dir = makeTempDir("slam_saved_map_" + std::to_string(::getpid()));
	const auto first =
		runProcess(binaryPath("lrgc-slam"),
				   {"--input", senaRawlogPath(), "--out", dir + "/first", "--quiet"});
	ASSERT_EQ(first.exitCode, 0) << first.output;
	const size_t oldNodes = graphNodes(dir + "/first");

	const auto cont = runProcess(binaryPath("lrgc-slam"),
								 {"--input", senaRawlogPath(), "--initial-map", dir + "/first",
								  "--out", dir + "/cont", "--quiet"});
	ASSERT_EQ(cont.exitCode, 0) << cont.output;
	EXPECT_NE(cont.output.find("the log starts at"), std::string::npos) << cont.output;
	EXPECT_GT(graphNodes(dir + "/cont"), oldNodes);  // the whole map: old + new
	EXPECT_EQ(field(readTextFile(dir + "/cont/stats.json"), "scans"),
			  field(readTextFile(dir + "/first/stats.json"), "scans"));

	const auto loc =
		runProcess(binaryPath("lrgc-slam"), {"--input", senaRawlogPath(), "--localize",
											 dir + "/first", "--out", dir + "/loc", "--quiet"});
	ASSERT_EQ(loc.exitCode, 0) << loc.output;
	const std::string stats = readTextFile(dir + "/loc/stats.json");
	EXPECT_EQ(field(stats, "localized_scans"), field(stats, "scans"));
	EXPECT_FALSE(fileExists(dir + "/loc/map.simplemap.gz"));
	EXPECT_TRUE(fileExists(dir + "/loc/trajectory.tum"));
}

TEST(SlamSavedMap, icpSlamsSimplemapIsContinued)
{
	LRGC_SKIP_IF_MISSING(senaRawlogPath());
	if (!fileExists(kIcpSlam)) GTEST_SKIP() << kIcpSlam << " not installed (mrpt-apps)";
	const std::string dir = makeTempDir("slam_saved_map_icp_" + std::to_string(::getpid()));
	std::string ini =
		readTextFile(std::string(LRGC_SOURCE_DIR) + "/bench/icp-slam_headless.ini");
	const auto p = ini.find("logOutput_dir=");
	ASSERT_NE(p, std::string::npos);
	ini.replace(p, ini.find('\n', p) - p, "logOutput_dir=" + dir + "/icp");
	writeTextFile(dir + "/icp.ini", ini);
	const auto icp = runProcess(kIcpSlam, {dir + "/icp.ini", senaRawlogPath()}, dir);
	ASSERT_EQ(icp.exitCode, 0) << icp.output;
	const std::string simplemap = dir + "/icp/_finalmap_.simplemap";
	ASSERT_TRUE(fileExists(simplemap));

	const auto cont =
		runProcess(binaryPath("lrgc-slam"), {"--input", senaRawlogPath(), "--initial-map",
											 simplemap, "--out", dir + "/cont", "--quiet"});
	ASSERT_EQ(cont.exitCode, 0) << cont.output;
	EXPECT_NE(cont.output.find("linked anew from the keyframes' poses"), std::string::npos);
	const auto loc =
		runProcess(binaryPath("lrgc-slam"), {"--input", senaRawlogPath(), "--localize",
											 simplemap, "--out", dir + "/loc", "--quiet"});
	ASSERT_EQ(loc.exitCode, 0) << loc.output;
}

TEST(SlamSavedMap, badArgumentsAndMapsAreOneLineErrors)
{
	const std::string dir = makeTempDir("slam_saved_map_bad_" + std::to_string(::getpid()));
	const std::string log = senaRawlogPath();
	const auto both = runProcess(
		binaryPath("lrgc-slam"),
		{"--input", log, "--initial-map", dir, "--localize", dir, "--out", dir + "/o"});
	EXPECT_EQ(both.exitCode, 2);
	EXPECT_NE(both.output.find("--initial-map and --localize exclude each other"),
			  std::string::npos)
		<< both.output;
	const auto noInput =
		runProcess(binaryPath("lrgc-slam"), {"--localize", dir, "--out", dir + "/o"});
	EXPECT_EQ(noInput.exitCode, 2);
	EXPECT_NE(noInput.output.find("--localize needs --input FILE"), std::string::npos)
		<< noInput.output;

	LRGC_SKIP_IF_MISSING(log);
	const auto missing = runProcess(
		binaryPath("lrgc-slam"),
		{"--input", log, "--initial-map", dir + "/nothing", "--out", dir + "/o", "--quiet"});
	EXPECT_EQ(missing.exitCode, 1);
	EXPECT_NE(
		missing.output.find("--initial-map '" + dir + "/nothing': no such file or folder"),
		std::string::npos)
		<< missing.output;
	const auto notAMap = runProcess(binaryPath("lrgc-slam"), {"--input", log, "--localize", log,
															  "--out", dir + "/o", "--quiet"});
	EXPECT_EQ(notAMap.exitCode, 1);
	EXPECT_NE(notAMap.output.find("not a readable MRPT CSimpleMap"), std::string::npos)
		<< notAMap.output;
	const auto notAFolder =
		runProcess(binaryPath("lrgc-slam"),
				   {"--input", log, "--localize", dir, "--out", dir + "/o", "--quiet"});
	EXPECT_EQ(notAFolder.exitCode, 1);
	EXPECT_NE(notAFolder.output.find("the folder has no map.simplemap.gz"), std::string::npos)
		<< notAFolder.output;
}
