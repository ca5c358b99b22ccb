/* End to end: no output of lrgc-slam, lrgc-eval or lrgc-plot is ever written over one of its
 * inputs (issue 30). Each run below would have replaced an input; each must be refused before
 * any work with exit 2 and one line naming both paths, and the input must be unchanged.
 * Paths are compared by identity: a symbolic link or a "sub/.." detour is caught too. */
#include <gtest/gtest.h>

#include <filesystem>

#include "app_runner.h"
#include "io_test_files.h"
#include "room_log.h"
#include "test_data.h"

namespace fs = std::filesystem;
using namespace lrgc::test;

namespace
{
// One mapped room (a saved map with every output) shared by the tests of this file.
class OutputsOverInputs : public ::testing::Test
{
protected:
	static void SetUpTestSuite()
	{
		s_dir = makeTempDir("outputs_over_inputs_" + std::to_string(::getpid()));
		writeTextFile(s_dir + "/room.clf", roomLog());
		s_map = s_dir + "/map";
		s_mapped = runProcess(binaryPath("lrgc-slam"),
							  {"--input", s_dir + "/room.clf", "--out", s_map, "--quiet"});
	}
	void SetUp() override { ASSERT_EQ(s_mapped.exitCode, 0) << s_mapped.output; }

	// Runs `program args`, expects the refusal naming `input` and `input` unchanged.
	static void expectRefused(const std::string& program, const std::vector<std::string>& args,
							  const std::string& input)
	{
		const std::string before = readFileBytes(input);
		const auto r = runProcess(binaryPath(program), args);
		EXPECT_EQ(r.exitCode, 2) << r.output;
		EXPECT_NE(r.output.find("never written over an input"), std::string::npos) << r.output;
		EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
		EXPECT_TRUE(readFileBytes(input) == before) << input << " was changed";
	}
	static inline std::string s_dir, s_map;
	static inline TProcessResult s_mapped;
};
}  // namespace

TEST_F(OutputsOverInputs, SlamInputInsideOutFolderUnderAnOutputName)
{
	const std::string dir = s_dir + "/a";
	fs::create_directories(dir);
	fs::copy_file(s_dir + "/room.clf", dir + "/timing.csv");
	expectRefused("lrgc-slam", {"--input", dir + "/timing.csv", "--out", dir},
				  dir + "/timing.csv");
	EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1)
		<< "the refused run wrote into " << dir;
}

TEST_F(OutputsOverInputs, SlamSeesThroughSymlinksAndDetours)
{
	const std::string dir = s_dir + "/b";
	fs::create_directories(dir + "/sub");
	fs::copy_file(s_dir + "/room.clf", dir + "/trajectory.tum");
	fs::create_directory_symlink(dir, s_dir + "/b-link");
	expectRefused("lrgc-slam",
				  {"--input", s_dir + "/b-link/trajectory.tum", "--out", dir + "/sub/.."},
				  dir + "/trajectory.tum");
	expectRefused("lrgc-slam",
				  {"--input", s_dir + "/room.clf", "--save-rawlog", dir + "/trajectory.tum",
				   "--config", s_dir + "/b-link/trajectory.tum"},
				  dir + "/trajectory.tum");
}

TEST_F(OutputsOverInputs, SlamNeverWritesIntoTheMapItLocalizesOn)
{
	for (const char* name : {"trajectory.tum", "timing.csv", "stats.json"})
		expectRefused("lrgc-slam",
					  {"--input", s_dir + "/room.clf", "--localize", s_map, "--out", s_map},
					  s_map + "/" + name);
	// A map file: its folder is the map's folder.
	expectRefused("lrgc-slam",
				  {"--input", s_dir + "/room.clf", "--localize", s_map + "/map.simplemap.gz",
				   "--out", s_map + "/."},
				  s_map + "/map.simplemap.gz");
}

TEST_F(OutputsOverInputs, SlamInitialMapIsNotRewrittenInPlace)
{
	expectRefused("lrgc-slam",
				  {"--input", s_dir + "/room.clf", "--initial-map", s_map, "--out", s_map},
				  s_map + "/graph.lrgc");
}

TEST_F(OutputsOverInputs, EvalJsonOverItsTrajectory)
{
	expectRefused("lrgc-eval",
				  {"--trajectory", s_map + "/trajectory.tum", "--ground-truth",
				   s_map + "/trajectory.tum", "--json", s_map + "/trajectory.tum"},
				  s_map + "/trajectory.tum");
}

TEST_F(OutputsOverInputs, PlotOutOverTheMapImage)
{
	const std::string before = readFileBytes(s_map + "/map.pgm");
	const auto r = runProcess(binaryPath("lrgc-plot"),
							  {"--map", s_map + "/map.yaml", "--trajectory",
							   s_map + "/trajectory.tum", "--out", s_map + "/map.pgm"});
	EXPECT_NE(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("never written over an input"), std::string::npos) << r.output;
	EXPECT_NE(r.output.find("map.pgm"), std::string::npos) << r.output;
	EXPECT_TRUE(readFileBytes(s_map + "/map.pgm") == before);
}

// Issue 30: a folder under an output's name (DIR/map.png/) was found only when the run tried
// to rename map.png into place, after the whole mapping, and the outputs after it were lost.
TEST_F(OutputsOverInputs, OutputNameTakenByAFolderIsFoundBeforeTheRun)
{
	const std::string dir = s_dir + "/c";
	fs::create_directories(dir + "/map.png");
	const auto r =
		runProcess(binaryPath("lrgc-slam"), {"--input", s_dir + "/room.clf", "--out", dir});
	EXPECT_EQ(r.exitCode, 2) << r.output;
	EXPECT_NE(r.output.find("--out: '" + dir + "/map.png' exists and is a folder"),
			  std::string::npos)
		<< r.output;
	EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1)
		<< "the refused run wrote into " << dir;
}
