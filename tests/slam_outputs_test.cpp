/* End to end: lrgc-slam on the real SENA rawlog (Debian mrpt-common) writes every output,
 * and MRPT reads each one back. */
#include <gtest/gtest.h>
#include <mrpt/graphs/CNetworkOfPoses.h>
#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CPointCloud.h>
#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/serialization/CArchive.h>

#include <sys/resource.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "app_runner.h"
#include "archive_gz.h"
#include "test_data.h"

namespace fs = std::filesystem;
using namespace lrgc::test;

namespace
{
// One lrgc-slam run on SENA shared by the tests of this file.
class SenaRun : public ::testing::Test
{
protected:
	static void SetUpTestSuite()
	{
		if (!fileExists(senaRawlogPath())) return;
		// CTest runs each test in its own process, two at a time: one directory per process.
		s_out = makeTempDir("sena_outputs_" + std::to_string(::getpid()));
		// An existing folder: a user's files, and an output of an earlier run.
		writeTextFile(out("notes.txt"), kNotes);
		fs::create_directory(out("earlier"));
		writeTextFile(out("earlier/map.png"), kNotes);
		writeTextFile(out("map.png"), "an earlier map");
		const double childCpu0 = childrenCpuSeconds();
		s_result =
			runProcess(binaryPath("lrgc-slam"), {"--input", senaRawlogPath(), "--out", s_out});
		s_childCpu = childrenCpuSeconds() - childCpu0;
	}
	// User + system time of this process's children waited for so far [s] (the shell
	// runProcess starts, lrgc-slam under it and its rawlog guard process).
	static double childrenCpuSeconds()
	{
		rusage ru{};
		::getrusage(RUSAGE_CHILDREN, &ru);
		return ru.ru_utime.tv_sec + 1e-6 * ru.ru_utime.tv_usec + ru.ru_stime.tv_sec +
			   1e-6 * ru.ru_stime.tv_usec;
	}
	void SetUp() override
	{
		LRGC_SKIP_IF_MISSING(senaRawlogPath());
		ASSERT_EQ(s_result.exitCode, 0) << s_result.output;
	}
	static std::string out(const std::string& name)
	{
		return (fs::path(s_out) / name).string();
	}
	static inline const std::string kNotes = "the user's own notes\n";
	static inline std::string s_out;
	static inline TProcessResult s_result;
	static inline double s_childCpu = 0;  //!< the run's CPU time, seen from outside [s]
};

size_t countLines(const std::string& path)
{
	std::ifstream f(path);
	size_t n = 0;
	for (std::string line; std::getline(f, line);)
		if (!line.empty()) ++n;
	return n;
}
}  // namespace

TEST_F(SenaRun, GridmapReadsBackAsOccupancyGrid)
{
	mrpt::maps::COccupancyGridMap2D grid;
	readArchiveGz(out("map.gridmap.gz"), grid);
	EXPECT_NEAR(grid.getResolution(), 0.05, 1e-6);
	// The SENA building is tens of metres across.
	EXPECT_GT(grid.getXMax() - grid.getXMin(), 10.0);
	EXPECT_GT(grid.getYMax() - grid.getYMin(), 10.0);
	size_t occupied = 0, freeCells = 0;
	for (unsigned y = 0; y < grid.getSizeY(); ++y)
		for (unsigned x = 0; x < grid.getSizeX(); ++x)
		{
			const float pFree = grid.getCell(x, y);  // MRPT stores p(free)
			occupied += pFree < 0.35f;
			freeCells += pFree > 0.65f;
		}
	EXPECT_GT(occupied, 1000u);
	EXPECT_GT(freeCells, 10 * occupied / 2);
}

TEST_F(SenaRun, SimplemapHasOneEntryPerKeyframe)
{
	mrpt::maps::CSimpleMap sm;
	readArchiveGz(out("map.simplemap.gz"), sm);
	const std::string stats = readTextFile(out("stats.json"));
	const auto pos = stats.find("\"keyframes\": ");
	ASSERT_NE(pos, std::string::npos);
	EXPECT_EQ(sm.size(), std::stoul(stats.substr(pos + 13)));
	EXPECT_GT(sm.size(), 20u);
}

TEST_F(SenaRun, GraphLoadsInMrptWithOneVertexPerKeyframe)
{
	mrpt::graphs::CNetworkOfPoses2DInf g;
	g.loadFromTextFile(out("graph.graph"));
	mrpt::maps::CSimpleMap sm;
	readArchiveGz(out("map.simplemap.gz"), sm);
	EXPECT_EQ(g.nodes.size(), sm.size());
	EXPECT_GE(g.edges.size(), g.nodes.size() - 1);
}

TEST_F(SenaRun, TrajectoryHasOneLinePerScanWithUnitQuaternions)
{
	// SENA has 225 scans: 224 action/observation pairs after a first sensory frame without
	// an action (MRPT's own tools skip that one and count 224).
	EXPECT_EQ(countLines(out("trajectory.tum")), 225u);
	std::ifstream f(out("trajectory.tum"));
	double t, x, y, z, qx, qy, qz, qw;
	while (f >> t >> x >> y >> z >> qx >> qy >> qz >> qw)
	{
		EXPECT_NEAR(qx * qx + qy * qy + qz * qz + qw * qw, 1.0, 1e-6);
		EXPECT_GT(t, 1137834225.0);  // the log's own timestamps (2006-01-21)
		EXPECT_LT(t, 1137834285.0);
	}
}

TEST_F(SenaRun, RosMapAndPngAreConsistent)
{
	const std::string yaml = readTextFile(out("map.yaml"));
	EXPECT_NE(yaml.find("image: map.pgm"), std::string::npos);
	EXPECT_NE(yaml.find("resolution: 0.05"), std::string::npos);
	const std::string pgm = readTextFile(out("map.pgm"));
	ASSERT_EQ(pgm.substr(0, 2), "P5");
	std::istringstream hdr(pgm.substr(2, 40));
	unsigned w = 0, h = 0;
	hdr >> w >> h;
	mrpt::img::CImage png;
	ASSERT_TRUE(png.loadFromFile(out("map.png")));
	ASSERT_EQ(png.getWidth(), w);
	ASSERT_EQ(png.getHeight(), h);
	// Same orientation (north up): the PNG's clearly free pixels are free in the PGM.
	const size_t header = pgm.size() - size_t(w) * h;
	size_t whitePng = 0, agree = 0;
	for (unsigned r = 0; r < h; r += 3)
		for (unsigned c = 0; c < w; c += 3)
			if (png.at<uint8_t>(c, r) > 240)
			{
				++whitePng;
				agree += static_cast<uint8_t>(pgm[header + size_t(r) * w + c]) == 254;
			}
	ASSERT_GT(whitePng, 1000u);
	EXPECT_GT(agree, whitePng * 9 / 10) << agree << " of " << whitePng;
}

TEST_F(SenaRun, AnExistingFolderKeepsEveryFileButOurOutputs)
{
	std::set<std::string> names;
	for (const auto& e : fs::directory_iterator(s_out))
		names.insert(e.path().filename().string());
	EXPECT_EQ(names, (std::set<std::string>{
						 "notes.txt", "earlier", "map.gridmap.gz", "map.png", "map.pgm",
						 "map.yaml", "map.simplemap.gz", "trajectory.tum", "graph.graph",
						 "graph.lrgc", "timing.csv", "stats.json", "config.ini",
						 "pf-localization.ini", "observations2map.ini", "map.3Dscene"}));
	EXPECT_EQ(readTextFile(out("notes.txt")), kNotes);
	EXPECT_EQ(readTextFile(out("earlier/map.png")), kNotes);
	EXPECT_NE(readTextFile(out("map.png")), "an earlier map");  // ours: replaced
}

TEST_F(SenaRun, ConsoleSaysWhatTheCountsCount)
{
	// One number of loop closures, the same on the console, in stats.json and (as links) in
	// graph.lrgc: "N loop closures (M loop links)".
	const std::regex summary(" ([0-9]+) loop closures \\(([0-9]+) loop links\\), ");
	std::smatch m;
	ASSERT_TRUE(std::regex_search(s_result.output, m, summary)) << s_result.output;
	const std::string stats = readTextFile(out("stats.json"));
	EXPECT_NE(stats.find("\"loop_closures\": " + m[1].str() + ",\n"), std::string::npos)
		<< stats;
	EXPECT_NE(stats.find("\"loop\": " + m[2].str() + "}"), std::string::npos) << stats;
	std::istringstream graph(readTextFile(out("graph.lrgc")));
	size_t loopLinks = 0;
	for (std::string line; std::getline(graph, line);)
		loopLinks +=
			line.rfind("LINK ", 0) == 0 && line.find(" LoopClosure ") != std::string::npos;
	EXPECT_EQ(std::to_string(loopLinks), m[2].str());
	// lrgc-plot draws the same loop links.
	const auto plot =
		runProcess(binaryPath("lrgc-plot"),
				   {"--map", out("map.yaml"), "--trajectory", out("trajectory.tum"), "--graph",
					out("graph.lrgc"), "--out", s_out + "-plot.png"});
	EXPECT_EQ(plot.exitCode, 0) << plot.output;
	EXPECT_NE(plot.output.find(", " + m[2].str() + " loop links, "), std::string::npos)
		<< plot.output;
	// A run that read its input to the end says so.
	EXPECT_NE(s_result.output.find("progress: 100.0%"), std::string::npos) << s_result.output;
}

TEST_F(SenaRun, StatsAndTimingAreWritten)
{
	const std::string stats = readTextFile(out("stats.json"));
	for (const char* key : {"\"scans\": 225", "\"latency_ms\"", "\"peak_rss_mb\"",
							"\"wall_time_s\"", "\"loop_closures\"", "\"status\": \"complete\""})
		EXPECT_NE(stats.find(key), std::string::npos) << key;
	// Loop closures (accepted matches with the old map), and the loop links by origin.
	const std::regex counts(
		"\"loop_links\": \\{\"closure\": ([0-9]+), \"revisit\": [0-9]+, "
		"\"rematch_or_reuse\": [0-9]+, \"rejected_at_end\": [0-9]+\\},\n  \"loop_closures\": "
		"([0-9]+),");
	std::smatch m;
	ASSERT_TRUE(std::regex_search(stats, m, counts)) << stats;
	EXPECT_EQ(m[1].str(), m[2].str());
	EXPECT_GT(std::stoi(m[1].str()), 0);             // SENA has a loop
	EXPECT_EQ(countLines(out("timing.csv")), 226u);  // header + one per scan
	for (const auto& e : fs::directory_iterator(s_out))
		EXPECT_EQ(e.path().filename().string().rfind(".tmp.", 0), std::string::npos)
			<< "temporary file left behind: " << e.path();
}

// stats.json "stages": every stage's CPU time, none negative, adding up to the process's CPU
// time the run reports, and that to the run's CPU time as the operating system counted it
// from outside (less: the guard process's second reading of the rawlog, the exit after
// stats.json); the shares add up to 1. CPU time, not wall: it holds on a loaded machine.
TEST_F(SenaRun, StatsStagesAddUpToTheProcessCpuTime)
{
	const std::string stats = readTextFile(out("stats.json"));
	const auto number = [&](const std::string& block, const std::string& key)
	{
		const size_t at = stats.find("\"" + block + "\": {");
		const size_t k = stats.find("\"" + key + "\": ", at);
		EXPECT_TRUE(at != std::string::npos && k != std::string::npos) << block << "." << key;
		return k == std::string::npos ? -1.0 : std::stod(stats.substr(k + key.size() + 4));
	};
	double cpuSum = 0, shareSum = 0;
	for (const char* stage : {"start_up", "input", "local_registration", "keyframe_patch",
							  "loop_closing_worker", "final_optimization", "outputs", "other"})
	{
		const double cpu = number("cpu_s", stage);
		EXPECT_GE(cpu, -1e-3) << stage;
		cpuSum += cpu;
		shareSum += number("cpu_share", stage);
	}
	const double processCpu = number("stages", "process_cpu_s");
	EXPECT_NEAR(cpuSum, processCpu, 1e-4);
	EXPECT_NEAR(shareSum, 1.0, 1e-4);
	EXPECT_GT(number("cpu_s", "local_registration"), 0);
	EXPECT_GT(number("cpu_s", "loop_closing_worker"), 0);  // SENA has a loop
	EXPECT_GT(number("stages", "mapping_cpu_ms_per_scan"), 0);
	EXPECT_LE(processCpu, s_childCpu + 0.02);
	EXPECT_GE(processCpu, 0.85 * s_childCpu - 0.1) << "the stages miss part of the run";
}

// map.3Dscene: MRPT's COpenGLScene (SceneViewer3D's format) loads it back, with the grid,
// the trajectory (a segment per pair of consecutive scans) and the loop links of graph.lrgc.
TEST_F(SenaRun, Scene3DLoadsWithGridTrajectoryAndLoopLinks)
{
	mrpt::opengl::COpenGLScene scene;
	mrpt::io::CFileGZInputStream f(out("map.3Dscene"));
	mrpt::serialization::archiveFrom(f) >> scene;
	ASSERT_TRUE(scene.getByName("gridmap"));
	const auto grid =
		std::dynamic_pointer_cast<mrpt::opengl::CSetOfObjects>(scene.getByName("gridmap"));
	ASSERT_TRUE(grid);
	EXPECT_GT(grid->size(), 0u);
	const auto path =
		std::dynamic_pointer_cast<mrpt::opengl::CSetOfLines>(scene.getByName("trajectory"));
	ASSERT_TRUE(path);
	EXPECT_EQ(path->getLineCount(), 224u);  // 225 scans
	const auto loops =
		std::dynamic_pointer_cast<mrpt::opengl::CSetOfLines>(scene.getByName("loop_links"));
	ASSERT_TRUE(loops);
	std::istringstream graph(readTextFile(out("graph.lrgc")));
	size_t loopLinks = 0;
	for (std::string line; std::getline(graph, line);)
		loopLinks +=
			line.rfind("LINK ", 0) == 0 && line.find(" LoopClosure 1") != std::string::npos;
	EXPECT_GT(loopLinks, 0u);
	EXPECT_EQ(loops->getLineCount(), loopLinks);
	const auto nodes =
		std::dynamic_pointer_cast<mrpt::opengl::CPointCloud>(scene.getByName("keyframes"));
	ASSERT_TRUE(nodes);
	mrpt::maps::CSimpleMap sm;
	readArchiveGz(out("map.simplemap.gz"), sm);
	EXPECT_EQ(nodes->size(), sm.size());
}
