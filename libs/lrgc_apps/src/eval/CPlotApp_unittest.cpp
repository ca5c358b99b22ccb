/* lrgc-plot: readers of map.yaml, graph.graph, timing.csv (with malformed lines), and the
 * drawing itself: the trajectory and the loop-closure links land on the pixels the map's
 * resolution and origin say. */
#include <gtest/gtest.h>
#include "eval/CPlotApp.h"
#include "eval/plot_inputs.h"
#include <mrpt/core/exceptions.h>
#include <mrpt/img/CImage.h>
#include <error_of.h>
#include <io_test_files.h>
#include <test_data.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>

using namespace lrgc::apps::eval;

using lrgc::test::errorOf;
using lrgc::test::writeFileBytes;

namespace
{
/** A 200 x 100 free map at 0.1 m/pixel with its lower-left corner at (-10, -5) m. */
void writeMap(const std::string& dir)
{
	std::string pgm = "P5\n200 100\n255\n" + std::string(200 * 100, static_cast<char>(254));
	writeFileBytes(dir + "/map.pgm", pgm);
	writeFileBytes(dir + "/map.yaml",
				   "image: map.pgm\nresolution: 0.1\norigin: [-10.0, -5.0, 0.0]\nnegate: 0\n"
				   "occupied_thresh: 0.65\nfree_thresh: 0.196\n");
}
}  // namespace

TEST(PlotInputs, RosMapYaml)
{
	const std::string dir = lrgc::test::makeTempDir("plot_yaml");
	writeMap(dir);
	const auto info = loadRosMapYaml(dir + "/map.yaml");
	EXPECT_EQ(info.imagePath, dir + "/map.pgm");
	EXPECT_DOUBLE_EQ(info.resolution, 0.1);
	EXPECT_DOUBLE_EQ(info.origin.x, -10);
	EXPECT_DOUBLE_EQ(info.origin.y, -5);
	EXPECT_FALSE(info.negate);

	writeFileBytes(dir + "/bad.yaml", "image: m.pgm\nresolution: 0.05\norigin: [1, 2]\n");
	EXPECT_NE(errorOf([&] { loadRosMapYaml(dir + "/bad.yaml"); })
				  .find("bad.yaml:3: origin must be [x, y, yaw], got 2 numbers"),
			  std::string::npos);
	writeFileBytes(dir + "/nores.yaml", "image: m.pgm\norigin: [1, 2, 0]\n");
	EXPECT_NE(errorOf([&] { loadRosMapYaml(dir + "/nores.yaml"); }).find("no 'resolution:'"),
			  std::string::npos);
}

TEST(PlotInputs, GraphFileAndLoopClosureEdges)
{
	const std::string dir = lrgc::test::makeTempDir("plot_graph");
	writeFileBytes(dir + "/g.graph",
				   "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nVERTEX_SE2 20 2 0 0\nFIX 0\n"
				   "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\nEDGE_SE2 1 20 1 0 0 1 0 0 1 0 1\n"
				   "EDGE_SE2 20 0 1 0 0 1 0 0 1 0 1\n");
	const auto g = loadGraphFile(dir + "/g.graph");
	EXPECT_EQ(g.vertices.size(), 3u);
	EXPECT_DOUBLE_EQ(g.vertices.at(20).x, 2);
	ASSERT_EQ(g.edges.size(), 3u);
	const auto loops = loopClosureEdges(g, 10);
	ASSERT_EQ(loops.size(), 2u);  // 1 -> 20 and 20 -> 0 (gaps 19, 20), not 0 -> 1
	EXPECT_EQ(loops[1].first, 20u);
	EXPECT_EQ(loopClosureEdges(g, 19).size(), 1u);

	writeFileBytes(dir + "/bad.graph", "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1.5 0 0 0\n");
	EXPECT_NE(errorOf([&] { loadGraphFile(dir + "/bad.graph"); })
				  .find("bad.graph:2: VERTEX_SE2: vertex id 1.5"),
			  std::string::npos);
	writeFileBytes(dir + "/bad2.graph", "EDGE_SE2 0 1 0\n");
	EXPECT_NE(
		errorOf([&] { loadGraphFile(dir + "/bad2.graph"); }).find("bad2.graph:1: EDGE_SE2"),
		std::string::npos);
}

// graph.lrgc has link types: the loop links are its enabled LoopClosure links, whatever
// their id gap, and a ScanMatch link across many ids is not one (graph.graph cannot tell).
TEST(PlotInputs, TypedGraphGivesTheLoopLinksByType)
{
	const std::string dir = lrgc::test::makeTempDir("plot_lrgc");
	const std::string info = " 1 0 0 1 0 1 ";
	writeFileBytes(dir + "/graph.lrgc",
				   "LRGC_POSE_GRAPH 1\nNODE 0 0 0 0\nNODE 1 1 0 0\nNODE 2 2 0 0\nNODE 3 3 0 0\n"
				   "LINK 0 1 1 0 0" +
					   info +
					   "Odometry 1\n"
					   "LINK 0 3 3 0 0" +
					   info +
					   "ScanMatch 1\n"
					   "LINK 1 2 1 0 0" +
					   info +
					   "LoopClosure 1\n"
					   "LINK 0 2 2 0 0" +
					   info +
					   "LoopClosure 0\n"
					   "LINK 3 0 -3 0 0" +
					   info + "LoopClosure 1\n");
	const auto g = loadGraphFile(dir + "/graph.lrgc");
	EXPECT_EQ(g.vertices.size(), 4u);
	EXPECT_DOUBLE_EQ(g.vertices.at(3).x, 3);
	EXPECT_EQ(g.edges.size(), 4u);  // the disabled link is left out
	const auto loops = loopClosureEdges(g, 2);
	ASSERT_EQ(loops.size(), 2u);
	EXPECT_EQ(loops[0], std::make_pair(std::size_t{1}, std::size_t{2}));
	EXPECT_EQ(loops[1], std::make_pair(std::size_t{3}, std::size_t{0}));
}

TEST(PlotInputs, TimingCsv)
{
	const std::string dir = lrgc::test::makeTempDir("plot_timing");
	writeFileBytes(dir + "/t.csv",
				   "scan_index,timestamp,latency_ms\n0,100.5,3.25\n1,100.7,4\n");
	const auto t = loadTimingCsv(dir + "/t.csv");
	ASSERT_EQ(t.size(), 2u);
	EXPECT_EQ(t[1].scanIndex, 1u);
	EXPECT_DOUBLE_EQ(t[0].timestamp, 100.5);
	EXPECT_DOUBLE_EQ(t[0].latency_ms, 3.25);
	// --localize's timing.csv: two more columns.
	writeFileBytes(dir + "/l.csv",
				   "scan_index,timestamp,latency_ms,replay_wait_ms,cpu_ms\n"
				   "0,100.5,3.25,0,3.1\n");
	ASSERT_EQ(loadTimingCsv(dir + "/l.csv").size(), 1u);
	EXPECT_DOUBLE_EQ(loadTimingCsv(dir + "/l.csv")[0].latency_ms, 3.25);
	writeFileBytes(dir + "/bad.csv",
				   "scan_index,timestamp,latency_ms\n0,100.5,3.25\n1,100.7\n");
	EXPECT_NE(errorOf([&] { loadTimingCsv(dir + "/bad.csv"); }).find("bad.csv:3: expected"),
			  std::string::npos);
}

TEST(PlotApp, DrawsTrajectoryAndLoopLinksWhereTheMapSays)
{
	const std::string dir = lrgc::test::makeTempDir("plot_render");
	writeMap(dir);
	// Trajectory along y = 2 from x = -6 to 6; keyframes 0 (-6, -2) and 30 (6, -2) linked.
	std::ostringstream tum;
	for (int i = 0; i <= 120; ++i)
		tum << 100 + 0.1 * i << " " << -6 + 0.1 * i << " 2 0 0 0 0 1\n";
	writeFileBytes(dir + "/t.tum", tum.str());
	writeFileBytes(
		dir + "/g.graph",
		"VERTEX_SE2 0 -6 -2 0\nVERTEX_SE2 30 6 -2 0\nEDGE_SE2 0 30 12 0 0 1 0 0 1 0 1\n");
	writeFileBytes(dir + "/timing.csv",
				   "scan_index,timestamp,latency_ms\n0,100,2\n1,100.1,3\n2,100.2,40\n");
	TPlotOptions o;
	o.mapYaml = dir + "/map.yaml";
	o.trajectory = dir + "/t.tum";
	o.graph = dir + "/g.graph";
	o.timing = dir + "/timing.csv";
	o.out = dir + "/plot.png";
	const TPlotSummary s = CPlotApp::render(o);
	EXPECT_EQ(s.trajectoryPoses, 121u);
	EXPECT_EQ(s.loopLinks, 1u);
	EXPECT_EQ(s.timedScans, 3u);
	// The map (20 m x 10 m plus a 1 m margin each side at 0.1 m/px) fills the 1200 px width.
	EXPECT_NEAR(s.pixelsPerMetre, 1200.0 / 22.0, 1e-9);

	mrpt::img::CImage img;  // reads the PNG back; channels in B, G, R order
	ASSERT_TRUE(img.loadFromFile(o.out));
	ASSERT_EQ(static_cast<int>(img.getWidth()), s.width);
	ASSERT_EQ(static_cast<int>(img.getHeight()), s.height);
	ASSERT_EQ(img.channelCount(), 3);
	struct Px
	{
		int b, g, r;
	};
	const auto at = [&](double x, double y)
	{
		const auto c =
			static_cast<unsigned>(std::lround(s.mapOriginCol + s.pixelsPerMetre * x));
		const auto r =
			static_cast<unsigned>(std::lround(s.mapOriginRow - s.pixelsPerMetre * y));
		return Px{img.at<uint8_t>(c, r, 0), img.at<uint8_t>(c, r, 1), img.at<uint8_t>(c, r, 2)};
	};
	const auto isBlue = [](const Px& p) { return p.b > 150 && p.r < 80; };
	const auto isRed = [](const Px& p) { return p.r > 150 && p.b < 80; };
	const auto isFree = [](const Px& p) { return p.b > 240 && p.g > 240 && p.r > 240; };
	EXPECT_TRUE(isBlue(at(0, 2)));
	EXPECT_TRUE(isBlue(at(3, 2)));
	EXPECT_TRUE(isRed(at(0, -2)));
	EXPECT_TRUE(isFree(at(0, 0)));
	EXPECT_TRUE(isFree(at(0, 4)));
	EXPECT_FALSE(isBlue(at(0, 0)));
}

TEST(PlotApp, HelpPrintsTheUsageAndSucceeds)
{
	for (const std::string h : {"--help", "-h"})
	{
		std::ostringstream out, err;
		EXPECT_EQ(CPlotApp::run({h}, out, err), 0) << h << ": " << err.str();
		EXPECT_NE(out.str().find("Usage: lrgc-plot"), std::string::npos) << out.str();
		EXPECT_TRUE(err.str().empty()) << err.str();
	}
}

TEST(PlotApp, VersionIsLrgcSlams)
{
	std::ostringstream out, err;
	EXPECT_EQ(CPlotApp::run({"--version"}, out, err), 0) << err.str();
	EXPECT_EQ(out.str(), std::string("lrgc-plot ") + LRGC_VERSION + "\n");
}

TEST(PlotApp, AUsageErrorIsOneLineNotTheWholeUsage)
{
	std::ostringstream out, err;
	EXPECT_EQ(CPlotApp::run({"--map", "m.yaml", "--bogus"}, out, err), 2);
	EXPECT_EQ(err.str(),
			  "lrgc-plot: unknown argument '--bogus'; lrgc-plot --help lists the options\n");
	EXPECT_TRUE(out.str().empty()) << out.str();
}

TEST(PlotApp, CommandLineErrors)
{
	std::ostringstream out, err;
	EXPECT_EQ(CPlotApp::run({"--map", "m.yaml"}, out, err), 2);
	EXPECT_EQ(CPlotApp::run({"--map", "m.yaml", "--trajectory", "t", "--out", "o.png",
							 "--loop-min-gap", "x"},
							out, err),
			  2);
	std::ostringstream err2;
	EXPECT_EQ(
		CPlotApp::run({"--map", "/nonexistent/m.yaml", "--trajectory", "t", "--out", "o.png"},
					  out, err2),
		1);
	EXPECT_NE(err2.str().find("/nonexistent/m.yaml: cannot open"), std::string::npos)
		<< err2.str();
}
