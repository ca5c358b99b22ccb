/* toMrptLeastSquares: one edge per node pair whose plain least-squares optimum is our
 * optimum. A simulated Manhattan graph gets a second, reversed link with a full information
 * matrix on every odometry pair and, for the robust case, false loop links; the exported
 * network, read back, is optimised without robust kernels from our poses and must not move
 * them. The .graph as it was (every link, unweighted) does move them: the tests can fail.
 * Measured: fused 0.47 mm, with DCS 0.63 mm (second order in the 2 cm residuals); the old
 * export 58 mm, the false links at full weight 0.29 m. */
#include <gtest/gtest.h>

#include <lrgc/common/se2.h>
#include <lrgc/pose_graph/GraphExport.h>
#include <lrgc/pose_graph/PoseGraphOptimizer.h>

#include <Eigen/Dense>
#include <random>
#include <set>

#include "manhattan_pose_graph.h"
#include "pose_graph_compare.h"
#include "test_data.h"

namespace
{
using namespace lrgc;
using mrpt::math::TPose2D;

/** Every odometry link gets a reversed twin (to -> from) measured anew from the truth with
 * noise of a full covariance (x and y correlated, 2 cm, 0.6 deg). */
void addReversedTwins(TSimulatedPoseGraph& sim, uint32_t seed)
{
	std::mt19937 rng(seed);
	std::normal_distribution<double> n(0, 1);
	Eigen::Matrix3d cov;
	cov << 4e-4, 2e-4, 0, 2e-4, 4e-4, 5e-5, 0, 5e-5, 1e-4;
	const Eigen::Matrix3d L = cov.llt().matrixL();
	const size_t links = sim.graph.numLinks();
	for (size_t id = 0; id < links; ++id)
	{
		const TLink l = sim.graph.link(id);
		if (l.type != LinkType::Odometry) continue;
		const Eigen::Vector3d e = L * Eigen::Vector3d(n(rng), n(rng), n(rng));
		const TPose2D truth = between(sim.groundTruth[l.to], sim.groundTruth[l.from]);
		sim.graph.addLink(
			{l.to, l.from, compose(truth, fromVector(e)), cov.inverse(), LinkType::ScanMatch});
	}
}

TPoseGraphOptimizerParams tight(bool robust)
{
	TPoseGraphOptimizerParams p;
	p.robust_loop_closures = robust;
	p.relative_cost_tolerance = 1e-12;
	p.step_tolerance = 1e-12;
	p.max_iterations = 200;
	return p;
}

/** The exported network as MRPT's .graph reader sees it (one edge per pair), back as ours. */
CPoseGraph throughGraphFile(const mrpt::graphs::CNetworkOfPoses2DInf& net,
							const std::string& name)
{
	const std::string file = lrgc::test::makeTempDir(name) + "/g.graph";
	net.saveToTextFile(file);
	mrpt::graphs::CNetworkOfPoses2DInf back;
	back.loadFromTextFile(file);
	return poseGraphFromMrpt(back);
}

size_t nodePairs(const CPoseGraph& g)
{
	std::set<std::pair<size_t, size_t>> pairs;
	for (size_t id = 0; id < g.numLinks(); ++id)
		if (g.isLinkEnabled(id))
			pairs.insert({std::min(g.link(id).from, g.link(id).to),
						  std::max(g.link(id).from, g.link(id).to)});
	return pairs.size();
}
}  // namespace

TEST(GraphExport, ParallelAndReversedLinksFuseIntoTheSameOptimum)
{
	// Scan-matching-like noise (2 cm, 0.6 deg per 1 m step): the fusion is exact to first
	// order in the residuals, so the optima differ by terms of their second order.
	auto sim = simulateManhattanPoseGraph(300, 8, 0.02, 0.01, 11);
	addReversedTwins(sim, 5);
	CPoseGraph ours = sim.graph;
	CPoseGraphOptimizer(tight(false)).optimize(ours, 0);

	const auto net = toMrptLeastSquares(ours, tight(false));
	EXPECT_EQ(net.edges.size(), nodePairs(ours));
	CPoseGraph fused = throughGraphFile(net, "graph_export_fused");
	ASSERT_EQ(fused.numNodes(), ours.numNodes());
	EXPECT_LT(test::maxPoseDifference(fused, ours), 1e-5);  // VERTEX_SE2 = our poses (text)
	CPoseGraphOptimizer(tight(false)).optimize(fused, 0);
	EXPECT_LT(test::maxPoseDifference(fused, ours), 1e-3);

	// The old export: every link written, the reader keeps one per pair.
	CPoseGraph collapsed = throughGraphFile(toMrpt(ours), "graph_export_collapsed");
	EXPECT_LT(collapsed.numLinks(), ours.numLinks());
	CPoseGraphOptimizer(tight(false)).optimize(collapsed, 0);
	EXPECT_GT(test::maxPoseDifference(collapsed, ours), 1e-2);
}

TEST(GraphExport, DownWeightedLoopLinksKeepTheRobustOptimum)
{
	auto sim = simulateManhattanPoseGraph(300, 8, 0.02, 0.01, 12);
	addReversedTwins(sim, 6);
	// Five false loop closures: 2 m and 30 deg away from the truth.
	for (size_t k = 0; k < 5; ++k)
	{
		const size_t from = 40 + 50 * k, to = from + 25;
		const TPose2D truth = between(sim.groundTruth[from], sim.groundTruth[to]);
		sim.graph.addLink({from, to, compose(truth, TPose2D(2.0, -1.0, 0.5)),
						   Eigen::Vector3d(400, 400, 2500).asDiagonal(),
						   LinkType::LoopClosure});
	}
	CPoseGraph ours = sim.graph;
	const auto rep = CPoseGraphOptimizer(tight(true)).optimize(ours, 0);
	ASSERT_GE(rep.downweightedLinks.size(), 5u);

	CPoseGraph lsq =
		throughGraphFile(toMrptLeastSquares(ours, tight(true)), "graph_export_dcs");
	CPoseGraphOptimizer(tight(false)).optimize(lsq, 0);
	EXPECT_LT(test::maxPoseDifference(lsq, ours), 1e-3);

	// Written with their full information, the false links bend the least-squares map.
	CPoseGraph unweighted =
		throughGraphFile(toMrptLeastSquares(ours, tight(false)), "graph_export_unweighted");
	CPoseGraphOptimizer(tight(false)).optimize(unweighted, 0);
	EXPECT_GT(test::maxPoseDifference(unweighted, ours), 0.1);
}

TEST(GraphExport, DisabledLinksAreNotWritten)
{
	CPoseGraph g;
	g.addNode({0, 0, 0});
	g.addNode({1, 0, 0});
	g.addNode({2, 0, 0});
	g.addLink({0, 1, {1, 0, 0}, Eigen::Matrix3d::Identity(), LinkType::Odometry});
	g.addLink({1, 2, {1, 0, 0}, Eigen::Matrix3d::Identity(), LinkType::Odometry});
	const size_t off =
		g.addLink({2, 0, {5, 5, 1}, Eigen::Matrix3d::Identity(), LinkType::LoopClosure});
	g.setLinkEnabled(off, false);
	const auto net = toMrptLeastSquares(g, {});
	EXPECT_EQ(net.edges.size(), 2u);
	EXPECT_EQ(net.nodes.size(), 3u);
}

TEST(GraphExport, AReversedLinkKeepsItsMeaning)
{
	// One link 1 -> 0 with a full information: written as 0 -> 1 with Z^-1; evaluated at
	// poses off its measurement, the chi2 of both directions agree to first order.
	const TPose2D z(0.8, 0.3, 0.4);  // (1 <- 0)
	Eigen::Matrix3d info;
	info << 200, 50, 10, 50, 300, -20, 10, -20, 900;
	CPoseGraph g;
	g.addNode({0, 0, 0});
	g.addNode(inverse(z));
	g.addLink({1, 0, z, info, LinkType::ScanMatch});
	const auto net = toMrptLeastSquares(g, {});
	ASSERT_EQ(net.edges.size(), 1u);
	const auto& [ends, edge] = *net.edges.begin();
	EXPECT_EQ(ends.first, 0u);
	EXPECT_EQ(ends.second, 1u);
	Eigen::Matrix3d infoOut;
	for (int r = 0; r < 3; ++r)
		for (int c = 0; c < 3; ++c) infoOut(r, c) = edge.cov_inv(r, c);
	const TPose2D zOut(edge.mean.x(), edge.mean.y(), edge.mean.phi());
	EXPECT_LT(test::maxPoseDifference(
				  [&]
				  {
					  CPoseGraph a;
					  a.addNode(zOut);
					  return a;
				  }(),
				  [&]
				  {
					  CPoseGraph a;
					  a.addNode(inverse(z));
					  return a;
				  }()),
			  1e-12);
	for (const TPose2D& d : {TPose2D(0.01, 0, 0), TPose2D(0, -0.01, 0), TPose2D(0, 0, 0.01),
							 TPose2D(0.005, 0.005, -0.005)})
	{
		const TPose2D x1 = compose(inverse(z), d);
		const Eigen::Vector3d e = linkResidual(x1, {0, 0, 0}, z);
		const Eigen::Vector3d eOut = linkResidual({0, 0, 0}, x1, zOut);
		const double chi2 = e.dot(info * e), chi2Out = eOut.dot(infoOut * eOut);
		EXPECT_NEAR(chi2Out, chi2, 0.02 * chi2) << d.x << " " << d.y << " " << d.phi;
	}
}
