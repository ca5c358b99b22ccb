/* CPoseGraph: validation, adjacency, disabling, the Manhattan simulator, and the round trip
 * through an MRPT .graph text file; the floor of a denoised scan's loop link (LinkNoise.h). */
#include <gtest/gtest.h>
#include <lrgc/pose_graph/LinkNoise.h>
#include <lrgc/pose_graph/GraphExport.h>
#include <lrgc/pose_graph/PoseGraph.h>
#include "manhattan_pose_graph.h"
#include <lrgc/pose_graph/PoseGraphOptimizer.h>
#include <lrgc/common/se2.h>
#include <mrpt/core/exceptions.h>

#include <algorithm>
#include <cmath>
#include <tuple>

#include "test_data.h"

using namespace lrgc;

namespace
{
CPoseGraph threeNodes()
{
	CPoseGraph g;
	g.addNode({0, 0, 0});
	g.addNode({1, 0, 0});
	g.addNode({2, 0, 0});
	return g;
}
}  // namespace

TEST(PoseGraph, AddLinkRejectsBadInput)
{
	CPoseGraph g = threeNodes();
	TLink ok{0, 1, {1, 0, 0}, Eigen::Matrix3d::Identity(), LinkType::Odometry};
	EXPECT_EQ(g.addLink(ok), 0u);

	TLink bad = ok;
	bad.to = 3;
	EXPECT_THROW(g.addLink(bad), std::exception);  // index out of range
	bad = ok;
	bad.to = 0;
	EXPECT_THROW(g.addLink(bad), std::exception);  // self link
	bad = ok;
	bad.information(0, 1) = 0.5;  // not symmetric
	EXPECT_THROW(g.addLink(bad), std::exception);
	bad = ok;
	bad.information(2, 2) = -1;  // not positive definite
	EXPECT_THROW(g.addLink(bad), std::exception);
	bad = ok;
	bad.information.setZero();  // singular
	EXPECT_THROW(g.addLink(bad), std::exception);
	bad = ok;
	bad.toInFrom.x = std::nan("");
	EXPECT_THROW(g.addLink(bad), std::exception);
	EXPECT_EQ(g.numLinks(), 1u);  // nothing half-added
	EXPECT_EQ(g.linksOf(0).size(), 1u);
	EXPECT_THROW(g.pose(3), std::exception);
	EXPECT_THROW(g.setLinkEnabled(1, false), std::exception);
}

TEST(PoseGraph, AdjacencyListsIncidentLinks)
{
	CPoseGraph g = threeNodes();
	const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
	const size_t a = g.addLink({0, 1, {1, 0, 0}, I, LinkType::Odometry});
	const size_t b = g.addLink({1, 2, {1, 0, 0}, I, LinkType::ScanMatch});
	const size_t c = g.addLink({2, 0, {-2, 0, 0}, I, LinkType::LoopClosure});
	EXPECT_EQ(g.linksOf(0), (std::vector<size_t>{a, c}));
	EXPECT_EQ(g.linksOf(1), (std::vector<size_t>{a, b}));
	EXPECT_EQ(g.linksOf(2), (std::vector<size_t>{b, c}));
}

TEST(PoseGraph, DisabledLinkIsIgnoredButKeepsItsId)
{
	CPoseGraph g = threeNodes();
	const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
	g.addLink({0, 1, {1, 0, 0}, I, LinkType::Odometry});
	const size_t wrong = g.addLink({0, 2, {5, 0, 0}, I, LinkType::LoopClosure});
	EXPECT_NEAR(totalChi2(g), 9.0, 1e-12);  // (5 - 2)^2
	g.setLinkEnabled(wrong, false);
	EXPECT_FALSE(g.isLinkEnabled(wrong));
	EXPECT_NEAR(totalChi2(g), 0.0, 1e-12);
	EXPECT_EQ(toMrpt(g).edges.size(), 1u);
	EXPECT_EQ(g.link(wrong).to, 2u);
	g.setLinkEnabled(wrong, true);
	EXPECT_NEAR(totalChi2(g), 9.0, 1e-12);
}

// What a copy of the graph kept elsewhere (the loop-closing worker's) must update: the lowest
// node moved since the last call; adding nodes is not moving them.
TEST(PoseGraph, LowestMovedNodeIsTrackedBetweenCalls)
{
	CPoseGraph g;
	for (int i = 0; i < 5; ++i) g.addNode({double(i), 0, 0});
	EXPECT_EQ(g.takeLowestMovedNode(), 5U);  // none moved
	g.setPose(3, {3, 1, 0});
	g.setPose(1, {1, 1, 0});
	g.setPose(4, {4, 1, 0});
	EXPECT_EQ(g.takeLowestMovedNode(), 1U);
	EXPECT_EQ(g.takeLowestMovedNode(), 5U);  // the count restarted
	g.addNode({5, 0, 0});
	g.setPose(4, {4, 2, 0});
	EXPECT_EQ(g.takeLowestMovedNode(), 4U);
}

// A map and a piece not yet joined to it (a session mapped in its own frame): the lowest node
// joined to a node is the first of its part; a disabled link joins nothing.
TEST(PoseGraph, LowestJoinedNodeIsTheFirstOfItsPart)
{
	CPoseGraph g;
	for (int i = 0; i < 6; ++i) g.addNode({double(i), 0, 0});
	const auto link = [&](size_t a, size_t b) {
		return g.addLink({a, b, {1, 0, 0}, Eigen::Matrix3d::Identity(), LinkType::Odometry});
	};
	link(0, 1), link(1, 2);  // the map
	link(3, 4), link(4, 5);  // the piece, from node 3
	EXPECT_EQ(g.lowestJoinedNode(2), 0U);
	EXPECT_EQ(g.lowestJoinedNode(5), 3U);
	EXPECT_EQ(g.lowestJoinedNode(3), 3U);
	const size_t join = link(1, 4);  // joined
	EXPECT_EQ(g.lowestJoinedNode(5), 0U);
	g.setLinkEnabled(join, false);
	EXPECT_EQ(g.lowestJoinedNode(5), 3U);
	EXPECT_THROW(g.lowestJoinedNode(6), std::exception);
}

TEST(PoseGraph, PoseAnglesAreWrapped)
{
	CPoseGraph g;
	g.addNode({0, 0, 3 * M_PI / 2});
	EXPECT_NEAR(g.pose(0).phi, -M_PI / 2, 1e-12);
	g.setPose(0, {1, 2, -3 * M_PI / 2});
	EXPECT_NEAR(g.pose(0).phi, M_PI / 2, 1e-12);
}

TEST(PoseGraph, SimulatorIsDeterministicAndConsistentWithTruth)
{
	const auto a = simulateManhattanPoseGraph(500, 8, 0.05, 0.01, 7);
	const auto b = simulateManhattanPoseGraph(500, 8, 0.05, 0.01, 7);
	ASSERT_EQ(a.graph.numNodes(), 500u);
	EXPECT_GT(a.numLoopClosures, 50u);
	EXPECT_EQ(a.graph.numLinks(), 499u + a.numLoopClosures);
	for (size_t i = 0; i < 500; ++i) EXPECT_EQ(a.graph.pose(i).x, b.graph.pose(i).x);
	// Measurement noise matches the stated sigmas: chi2 at the truth ~ 3 per link.
	CPoseGraph atTruth = a.graph;
	for (size_t i = 0; i < 500; ++i) atTruth.setPose(i, a.groundTruth[i]);
	const double perLink = totalChi2(atTruth) / double(a.graph.numLinks());
	EXPECT_NEAR(perLink, 3.0, 0.5);
	for (const TLink& l : a.graph.links())  // loop closures join poses in one grid cell
	{
		if (l.type == LinkType::LoopClosure)
		{
			EXPECT_LT(translationNorm(between(a.groundTruth[l.from], a.groundTruth[l.to])),
					  1e-9);
		}
	}
}

TEST(PoseGraph, RoundTripThroughMrptGraphFile)
{
	const auto sim = simulateManhattanPoseGraph(300, 6, 0.05, 0.01, 3);
	const std::string file = lrgc::test::makeTempDir("posegraph_roundtrip") + "/g.graph";
	toMrpt(sim.graph).saveToTextFile(file);

	mrpt::graphs::CNetworkOfPoses2DInf net;
	net.loadFromTextFile(file);
	const CPoseGraph back = poseGraphFromMrpt(net);
	ASSERT_EQ(back.numNodes(), sim.graph.numNodes());
	ASSERT_EQ(back.numLinks(), sim.graph.numLinks());
	// MRPT writes 6 significant digits.
	for (size_t i = 0; i < back.numNodes(); ++i)
	{
		const auto &p = back.pose(i), &q = sim.graph.pose(i);
		EXPECT_NEAR(p.x, q.x, 1e-5 * (1 + std::abs(q.x)));
		EXPECT_NEAR(p.y, q.y, 1e-5 * (1 + std::abs(q.y)));
		EXPECT_NEAR(std::remainder(p.phi - q.phi, 2 * M_PI), 0, 1e-5);
	}
	// The multimap reorders links by (from, to): compare sorted.
	auto key = [](const TLink& l) { return std::make_tuple(l.from, l.to, l.toInFrom.x); };
	auto sorted = [&](const CPoseGraph& g)
	{
		std::vector<TLink> v = g.links();
		std::sort(v.begin(), v.end(), [&](auto& a, auto& b) { return key(a) < key(b); });
		return v;
	};
	const auto la = sorted(back), lb = sorted(sim.graph);
	for (size_t k = 0; k < la.size(); ++k)
	{
		EXPECT_EQ(la[k].from, lb[k].from);
		EXPECT_EQ(la[k].to, lb[k].to);
		EXPECT_EQ(la[k].type, lb[k].type);  // consecutive -> Odometry, others LoopClosure
		EXPECT_NEAR(la[k].toInFrom.x, lb[k].toInFrom.x, 1e-5);
		EXPECT_NEAR(la[k].toInFrom.phi, lb[k].toInFrom.phi, 1e-5);
		EXPECT_TRUE(la[k].information.isApprox(lb[k].information, 1e-5));
	}
}

TEST(PoseGraph, FromMrptRejectsNonContiguousIds)
{
	mrpt::graphs::CNetworkOfPoses2DInf net;
	net.nodes[0] = mrpt::poses::CPose2D(0, 0, 0);
	net.nodes[2] = mrpt::poses::CPose2D(1, 0, 0);
	EXPECT_THROW(poseGraphFromMrpt(net), std::exception);
}

// A loop link's floor (LinkNoise.h): as configured for scans with their ranges as measured
// (rangeNoiseStd 0) or whose left noise is below half the floor, 2x the left noise above.
TEST(LinkNoise, DenoisedLoopLinkFloorIsTwiceTheNoiseLeft)
{
	const TLinkNoise configured{0.01, 0.25 * M_PI / 180};
	for (const double left : {0.0, 0.004, 0.005})
	{
		const TLinkNoise n = denoisedLoopLinkNoise(configured, left);
		EXPECT_EQ(n.floor_xy_m, configured.floor_xy_m) << left;
		EXPECT_EQ(n.floor_phi, configured.floor_phi) << left;
	}
	const TLinkNoise noisy = denoisedLoopLinkNoise(configured, 0.05);
	EXPECT_DOUBLE_EQ(noisy.floor_xy_m, 0.1);
	EXPECT_EQ(noisy.floor_phi, configured.floor_phi);  // the heading's floor as configured
	// The link's information: xy std sqrt(C + 0.1^2) along both axes.
	const Eigen::Matrix3d info = linkInformation(Eigen::Matrix3d::Identity() * 1e-4, noisy);
	EXPECT_NEAR(1 / std::sqrt(info(0, 0)), std::sqrt(1e-4 + 0.01), 1e-12);
}
