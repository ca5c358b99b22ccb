/* CPoseGraphOptimizer: false loop closures rejected by the robust kernel (DCS) without
 * bending the map, true loops (also with large drift) kept. */
#include <gtest/gtest.h>
#include <lrgc/pose_graph/PoseGraphOptimizer.h>
#include "manhattan_pose_graph.h"
#include <lrgc/common/se2.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>

#include "pose_graph_compare.h"
#include "test_data.h"

using namespace lrgc;
using lrgc::test::maxPoseDifference;
using lrgc::test::rmsPositionError;

namespace
{
struct TFalseLoopCase
{
	CPoseGraph correct;    // optimised graph with only true links
	CPoseGraph withFalse;  // the same plus false loop closures
	std::vector<size_t> falseIds;
	size_t numTrueLoops = 0;
};

/** A correct, optimised 1000-pose graph, then `count` loop closures between poses more
 * than 5 m apart, each claiming they are at the same place, with confident information. */
TFalseLoopCase makeFalseLoopCase(int count, uint32_t seed)
{
	const auto sim = simulateManhattanPoseGraph(1000, 12, 0.05, 0.01, seed);
	TFalseLoopCase c;
	c.correct = sim.graph;
	c.numTrueLoops = sim.numLoopClosures;
	for (int k = 0; k < 5 && !CPoseGraphOptimizer().optimize(c.correct, 0).converged; ++k)
	{
	}  // a cold start may need more than one call's iteration budget
	c.withFalse = c.correct;
	std::mt19937 rng(seed + 1);
	std::uniform_int_distribution<size_t> node(0, 999);
	std::normal_distribution<double> small(0.0, 0.1);
	const Eigen::Matrix3d info = Eigen::Vector3d(400, 400, 10000).asDiagonal();
	while (c.falseIds.size() < size_t(count))
	{
		const size_t i = node(rng), j = node(rng);
		if (translationNorm(between(sim.groundTruth[i], sim.groundTruth[j])) < 5.0) continue;
		c.falseIds.push_back(c.withFalse.addLink(
			{i, j, {small(rng), small(rng), small(rng)}, info, LinkType::LoopClosure}));
	}
	return c;
}
}  // namespace

TEST(PoseGraphOptimizer, FalseLoopClosuresAreRejectedAndDoNotBendTheMap)
{
	for (uint32_t seed : {31u, 32u, 33u})
	{
		TFalseLoopCase c = makeFalseLoopCase(10, seed);
		const TOptimizationReport rep = CPoseGraphOptimizer().optimize(c.withFalse, 0);
		EXPECT_TRUE(rep.converged);
		// Exactly the false links are reported: no true loop closure is rejected.
		EXPECT_EQ(rep.downweightedLinks, c.falseIds) << "seed " << seed;
		EXPECT_LT(maxPoseDifference(c.withFalse, c.correct), 0.01) << "seed " << seed;
	}
}

TEST(PoseGraphOptimizer, WithoutTheRobustKernelFalseLoopClosuresBendTheMap)
{
	TFalseLoopCase c = makeFalseLoopCase(10, 31);
	TPoseGraphOptimizerParams p;
	p.robust_loop_closures = false;
	const TOptimizationReport rep = CPoseGraphOptimizer(p).optimize(c.withFalse, 0);
	EXPECT_TRUE(rep.downweightedLinks.empty());
	EXPECT_GT(maxPoseDifference(c.withFalse, c.correct), 1.0);
}

TEST(PoseGraphOptimizer, TrueLoopsAddedIncrementallyAreAcceptedFalseOnesRejected)
{
	// As in the mapper: poses arrive one by one and the graph is optimised when a loop
	// closure arrives (at most every 10 poses), so a true loop arrives with the drift
	// accumulated since the last one. Every 40th pose also gets a confident false loop
	// closure to a pose more than 5 m away, claiming they are at the same place.
	const auto sim = simulateManhattanPoseGraph(1000, 16, 0.05, 0.01, 44);
	CPoseGraph g;
	g.addNode(sim.groundTruth[0]);
	const CPoseGraphOptimizer opt;
	std::vector<size_t> falseIds;
	std::mt19937 rng(5);
	size_t lastOptimized = 0;
	for (size_t id = 0; id < sim.graph.numLinks(); ++id)
	{
		const TLink& l = sim.graph.link(id);
		if (l.type == LinkType::Odometry) g.addNode(compose(g.pose(l.from), l.toInFrom));
		g.addLink(l);
		bool loop = l.type == LinkType::LoopClosure;
		if (l.type == LinkType::Odometry && l.to % 40 == 0)
		{
			const size_t far = std::uniform_int_distribution<size_t>(0, l.to / 2)(rng);
			if (translationNorm(between(sim.groundTruth[far], sim.groundTruth[l.to])) > 5.0)
			{
				falseIds.push_back(g.addLink({far,
											  l.to,
											  {0, 0, 0},
											  Eigen::Vector3d(400, 400, 10000).asDiagonal(),
											  LinkType::LoopClosure}));
				loop = true;
			}
		}
		if (loop && g.numNodes() >= lastOptimized + 10)
		{
			opt.optimize(g, 0);
			lastOptimized = g.numNodes();
		}
	}
	const TOptimizationReport rep = opt.optimize(g, 0);
	EXPECT_GT(falseIds.size(), 10u);
	EXPECT_EQ(rep.downweightedLinks, falseIds);
	// Compare with the least-squares solution of the true links only.
	CPoseGraph trueOnly = sim.graph;
	TPoseGraphOptimizerParams plain;
	plain.robust_loop_closures = false;
	CPoseGraphOptimizer(plain).optimize(trueOnly, 0);
	EXPECT_LT(rmsPositionError(g, trueOnly.poses()), 0.1);
}

TEST(PoseGraphOptimizer, ABigLoopWithLargeDriftIsClosedAndAFalseOneIsNot)
{
	// One 30 m x 30 m square corridor loop of 120 poses, closed once at the end. The drift
	// of dead reckoning at the closure is metres, far beyond the loop link's own sigma
	// (5 cm): plain DCS would give it a weight near 0 (s < 0.03) and leave the loop open.
	// It is consistent with the odometry's covariance, so the back-end must close it; a
	// confident false loop across the square must stay rejected.
	const double sxy = 0.05, sphi = 0.01;
	const Eigen::Matrix3d info =
		Eigen::Vector3d(1 / (sxy * sxy), 1 / (sxy * sxy), 1 / (sphi * sphi)).asDiagonal();
	std::vector<TPose2D> truth;
	for (int i = 0; i < 120; ++i)
	{
		const int side = i / 30, along = i % 30;
		const double c[4][2] = {{0, 0}, {30, 0}, {30, 30}, {0, 30}};
		const double dir[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
		truth.push_back({c[side][0] + along * dir[side][0], c[side][1] + along * dir[side][1],
						 mrpt::math::wrapToPi(side * M_PI / 2)});
	}
	CPoseGraph g;
	for (uint32_t seed = 1;; ++seed)  // first seed whose closure error exceeds 2 m
	{
		std::mt19937 rng(seed);
		std::normal_distribution<double> n01;
		g = CPoseGraph();
		g.addNode(truth[0]);
		for (size_t i = 1; i < 120; ++i)
		{
			const TPose2D z = compose(between(truth[i - 1], truth[i]),
									  {sxy * n01(rng), sxy * n01(rng), sphi * n01(rng)});
			g.addNode(compose(g.pose(i - 1), z));
			g.addLink({i - 1, i, z, info, LinkType::Odometry});
		}
		if (translationNorm(between(g.pose(119), g.pose(0))) > 2.0 + 1.0) break;
		ASSERT_LT(seed, 1000u);
	}
	const size_t trueLoop =
		g.addLink({119, 0, between(truth[119], truth[0]), info, LinkType::LoopClosure});
	const size_t falseLoop = g.addLink({15, 75, {0, 0, 0}, info, LinkType::LoopClosure});
	// Reference: least squares on the true links only.
	CPoseGraph ideal = g;
	ideal.setLinkEnabled(falseLoop, false);
	TPoseGraphOptimizerParams plain;
	plain.robust_loop_closures = false;
	CPoseGraphOptimizer(plain).optimize(ideal, 0);
	const double before = rmsPositionError(g, truth);
	const TOptimizationReport rep = CPoseGraphOptimizer().optimize(g, 0);
	EXPECT_TRUE(rep.converged);
	EXPECT_EQ(rep.downweightedLinks, std::vector<size_t>{falseLoop});
	const TLink& l = g.link(trueLoop);
	const Eigen::Vector3d e = linkResidual(g.pose(l.from), g.pose(l.to), l.toInFrom);
	EXPECT_LT(e.dot(l.information * e), 5.0);  // closed: back in DCS's quadratic zone
	EXPECT_LT(rmsPositionError(g, ideal.poses()), 0.02);
	EXPECT_LT(rmsPositionError(g, truth), 0.5 * before) << "before " << before;
}
