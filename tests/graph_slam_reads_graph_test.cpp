/* Our graph.graph as MRPT reads it (issue 14, item 5): lrgc-slam maps the SENA rawlog (Debian
 * mrpt-common); MRPT's real `graph-slam --2d --info` (Debian mrpt-apps) must read every edge
 * of its graph.graph (MRPT's reader keeps one edge per node pair: ours are fused per pair),
 * and MRPT's sparse Levenberg-Marquardt (mrpt::graphslam::optimize_graph_spa_levmarq) on the
 * graph read by MRPT's CNetworkOfPoses2DInf::loadFromTextFile must find our poses: no node
 * moved by more than 1 cm or 0.1 degree.
 * Before the fusion MRPT kept 748 of 1074 edges and its optimiser moved nodes by 0.062 m.
 * Not `graph-slam --levmarq` itself: that program loads a CNetworkOfPoses2D, whose edges'
 * information MRPT's optimiser ignores (unit weights), so no graph with real information
 * matrices keeps its optimum there (ours: 0.235 m; doc/back-end.md). */
#include <gtest/gtest.h>
#include <mrpt/graphs/CNetworkOfPoses.h>
#include <mrpt/graphslam/levmarq.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include "app_runner.h"
#include "test_data.h"

using namespace lrgc::test;

namespace
{
struct TVertex
{
	double x = 0, y = 0, phi = 0;
};

std::map<int, TVertex> readVertices(const std::string& path)
{
	std::ifstream f(path);
	std::map<int, TVertex> v;
	std::string line;
	while (std::getline(f, line))
	{
		std::istringstream in(line);
		std::string tag;
		int id;
		TVertex p;
		if (in >> tag && tag == "VERTEX_SE2" && in >> id >> p.x >> p.y >> p.phi) v[id] = p;
	}
	return v;
}

size_t countLinesStartingWith(const std::string& path, const std::string& tag)
{
	std::ifstream f(path);
	size_t n = 0;
	for (std::string line; std::getline(f, line);) n += line.rfind(tag, 0) == 0 ? 1 : 0;
	return n;
}
}  // namespace

TEST(GraphSlamReadsGraph, MrptKeepsEveryEdgeAndItsOptimiserOurPoses)
{
	const std::string sena = senaRawlogPath();
	LRGC_SKIP_IF_MISSING(sena);
	if (std::system("command -v graph-slam >/dev/null 2>&1") != 0)
		GTEST_SKIP() << "MRPT's graph-slam program is not installed (Debian package mrpt-apps)";
	const std::string dir = makeTempDir("graph_slam_reads_graph");
	const auto run =
		runProcess(binaryPath("lrgc-slam"), {"--input", sena, "--out", dir, "--quiet"});
	ASSERT_EQ(run.exitCode, 0) << run.output;
	const std::string graph = dir + "/graph.graph";
	const size_t edges = countLinesStartingWith(graph, "EDGE_SE2 ");
	ASSERT_GT(edges, 300u);

	const auto info = runProcess("graph-slam", {"--2d", "--info", "-i", graph});
	ASSERT_EQ(info.exitCode, 0) << info.output;
	std::smatch m;
	ASSERT_TRUE(std::regex_search(info.output, m, std::regex(R"(Edge count\s*:\s*([0-9]+))")))
		<< info.output;
	EXPECT_EQ(std::stoul(m[1]), edges) << "graph-slam dropped edges it reads as duplicates";

	mrpt::graphs::CNetworkOfPoses2DInf net;
	net.loadFromTextFile(graph);
	ASSERT_EQ(net.edges.size(), edges);
	net.root = 0;
	mrpt::containers::yaml params;
	params["max_iterations"] = 100;
	mrpt::graphslam::TResultInfoSpaLevMarq result;
	mrpt::graphslam::optimize_graph_spa_levmarq(net, result, nullptr, params);
	net.saveToTextFile(dir + "/optimized.graph");
	const auto ours = readVertices(graph), theirs = readVertices(dir + "/optimized.graph");
	ASSERT_GT(ours.size(), 100u);
	ASSERT_EQ(theirs.size(), ours.size());
	double worstXY = 0, worstPhi = 0;
	int worstNode = -1;
	for (const auto& [id, p] : ours)
	{
		const TVertex& q = theirs.at(id);
		const double dxy = std::hypot(q.x - p.x, q.y - p.y);
		if (dxy > worstXY) worstXY = dxy, worstNode = id;
		worstPhi = std::max(worstPhi, std::abs(std::remainder(q.phi - p.phi, 2 * M_PI)));
	}
	EXPECT_LT(worstXY, 0.01) << "node " << worstNode << " moved by " << worstXY << " m";
	EXPECT_LT(worstPhi, 0.1 * M_PI / 180) << worstPhi * 180 / M_PI << " deg";
	std::printf(
		"MRPT's levmarq on SENA's graph.graph: %zu edges, %zu iterations, largest move "
		"%.4f m (node %d), %.4f deg\n",
		edges, result.num_iters, worstXY, worstNode, worstPhi * 180 / M_PI);
}
