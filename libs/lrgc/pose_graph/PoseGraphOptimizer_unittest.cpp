/* CPoseGraphOptimizer: residual Jacobians, convergence to ground truth, MRPT's reference
 * optimiser, windowed solves, parameters. False loop closures:
 * PoseGraphOptimizerRobust_unittest. */
#include <gtest/gtest.h>
#include <lrgc/pose_graph/GraphExport.h>
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

TEST(PoseGraphOptimizer, ResidualJacobiansMatchNumericDifferences)
{
	std::mt19937 rng(1);
	std::uniform_real_distribution<double> pos(-5, 5), ang(-M_PI, M_PI);
	const double h = 1e-6;
	for (int trial = 0; trial < 200; ++trial)
	{
		TPose2D xi{pos(rng), pos(rng), ang(rng)}, xj{pos(rng), pos(rng), ang(rng)};
		const TPose2D z{pos(rng), pos(rng), ang(rng)};
		if (trial < 4) xi.phi = (trial % 2 ? 1 : -1) * (M_PI - 1e-9);  // at the wrap
		Eigen::Matrix3d Ji, Jj;
		const Eigen::Vector3d e0 = linkResidual(xi, xj, z, &Ji, &Jj);
		for (int k = 0; k < 3; ++k)
		{
			const auto bump = [&](TPose2D p, double d)
			{
				(k == 0 ? p.x : k == 1 ? p.y : p.phi) += d;
				return p;
			};
			const auto diff = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b)
			{
				Eigen::Vector3d d = a - b;
				d.z() = mrpt::math::wrapToPi(d.z());
				return d;
			};
			const Eigen::Vector3d ni =
				diff(linkResidual(bump(xi, h), xj, z), linkResidual(bump(xi, -h), xj, z)) /
				(2 * h);
			const Eigen::Vector3d nj =
				diff(linkResidual(xi, bump(xj, h), z), linkResidual(xi, bump(xj, -h), z)) /
				(2 * h);
			EXPECT_LT((ni - Ji.col(k)).cwiseAbs().maxCoeff(), 1e-6) << "trial " << trial;
			EXPECT_LT((nj - Jj.col(k)).cwiseAbs().maxCoeff(), 1e-6) << "trial " << trial;
		}
		EXPECT_LE(std::abs(e0.z()), M_PI);
	}
}

TEST(PoseGraphOptimizer, ResidualIsZeroForAConsistentMeasurementAcrossTheWrap)
{
	const TPose2D xi{1, 2, 3.1}, xj{-2, 0.5, -3.0};
	const Eigen::Vector3d e = linkResidual(xi, xj, between(xi, xj));
	EXPECT_LT(e.cwiseAbs().maxCoeff(), 1e-12);
}

TEST(PoseGraphOptimizer, ParamsRoundTripAndRejectUnknownKeys)
{
	TPoseGraphOptimizerParams p;
	p.max_iterations = 17;
	p.dcs_phi = 2.5;
	p.robust_loop_closures = false;
	mrpt::config::CConfigFileMemory saved;
	p.saveToConfigFile(saved, "PoseGraphOptimizer");
	const mrpt::config::CConfigFileMemory mem(saved.getContent());  // as text, like an .ini
	TPoseGraphOptimizerParams q;
	q.loadFromConfigFile(mem, "PoseGraphOptimizer");
	EXPECT_EQ(q.max_iterations, 17);
	EXPECT_EQ(q.dcs_phi, 2.5);
	EXPECT_FALSE(q.robust_loop_closures);
	EXPECT_EQ(q.reject_scale, p.reject_scale);

	mrpt::config::CConfigFileMemory typo;
	typo.write("PoseGraphOptimizer", "dcs_phy", 3.0);
	EXPECT_THROW(q.loadFromConfigFile(typo, "PoseGraphOptimizer"), std::exception);
	mrpt::config::CConfigFileMemory invalid;
	invalid.write("PoseGraphOptimizer", "reject_scale", 1.5);
	EXPECT_THROW(q.loadFromConfigFile(invalid, "PoseGraphOptimizer"), std::exception);
}

TEST(PoseGraphOptimizer, SquareLoopConvergesToGroundTruth)
{
	// 2 m square, 8 poses, exact measurements, the loop closed 7 -> 0; start from a bent guess.
	std::vector<TPose2D> truth;
	for (int i = 0; i < 8; ++i)
	{
		const int side = i / 2, along = i % 2;
		const double c[4][2] = {{0, 0}, {2, 0}, {2, 2}, {0, 2}};
		const double dir[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
		truth.push_back({c[side][0] + along * dir[side][0], c[side][1] + along * dir[side][1],
						 mrpt::math::wrapToPi(side * M_PI / 2)});
	}
	CPoseGraph g;
	const Eigen::Matrix3d info = Eigen::Vector3d(100, 100, 400).asDiagonal();
	for (int i = 0; i < 8; ++i)
		g.addNode(compose(truth[i], {0.1 * i, -0.05 * i, 0.08 * i}));  // drifting guess
	g.setPose(0, truth[0]);
	for (size_t i = 0; i < 8; ++i)
		g.addLink({i, (i + 1) % 8, between(truth[i], truth[(i + 1) % 8]), info,
				   i == 7 ? LinkType::LoopClosure : LinkType::Odometry});
	const CPoseGraphOptimizer opt;
	const TOptimizationReport rep = opt.optimize(g, 0);
	EXPECT_TRUE(rep.converged);
	EXPECT_GT(rep.initialChi2, 10.0);
	EXPECT_LT(rep.finalChi2, 1e-12);
	EXPECT_EQ(rep.numFreeNodes, 7u);
	EXPECT_TRUE(rep.downweightedLinks.empty());
	for (size_t i = 0; i < 8; ++i)
	{
		EXPECT_NEAR(g.pose(i).x, truth[i].x, 1e-7);
		EXPECT_NEAR(g.pose(i).y, truth[i].y, 1e-7);
		EXPECT_NEAR(mrpt::math::wrapToPi(g.pose(i).phi - truth[i].phi), 0, 1e-7);
	}
}

// Issue 30: a stop request ends a solve before its next iteration, the poses at the last
// accepted iterate (as they were if no iteration ran), report.stopped set.
TEST(PoseGraphOptimizer, StopRequestEndsTheSolveBeforeItsNextIteration)
{
	const auto bentSquare = []
	{
		CPoseGraph g;
		const Eigen::Matrix3d info = Eigen::Vector3d(100, 100, 400).asDiagonal();
		for (int i = 0; i < 8; ++i) g.addNode({0.3 * i, 0.1 * i * i, 0.2 * i});
		for (size_t i = 0; i < 8; ++i)
			g.addLink({i, (i + 1) % 8, TPose2D(1, 0, M_PI / 4), info, LinkType::Odometry});
		return g;
	};
	CPoseGraphOptimizer opt;
	CPoseGraph whole = bentSquare();
	const TOptimizationReport full = opt.optimize(whole, 0);
	ASSERT_GT(full.iterations, 2);
	EXPECT_FALSE(full.stopped);

	const CStopSource source;
	opt.setStopToken(source.token());
	int iterations = 0;  // the stop comes during the second iteration
	opt.setIterationCallback(
		[&]
		{
			if (++iterations == 2) source.requestStop();
		});
	CPoseGraph cut = bentSquare();
	const TOptimizationReport rep = opt.optimize(cut, 0);
	EXPECT_TRUE(rep.stopped);
	EXPECT_FALSE(rep.converged);
	EXPECT_EQ(rep.iterations, 2);
	EXPECT_LT(rep.finalChi2, rep.initialChi2);  // two accepted steps were kept
	EXPECT_GT(rep.finalChi2, full.finalChi2);

	CPoseGraph untouched = bentSquare();
	const TOptimizationReport none = opt.optimize(untouched, 0);  // stopped already
	EXPECT_TRUE(none.stopped);
	EXPECT_EQ(none.iterations, 0);
	for (size_t i = 0; i < untouched.numNodes(); ++i)
		EXPECT_EQ(untouched.pose(i), bentSquare().pose(i)) << i;
}

TEST(PoseGraphOptimizer, ManhattanGraphOf3000PosesRecoversGroundTruth)
{
	const auto sim = simulateManhattanPoseGraph(3000, 25, 0.05, 0.01, 11);
	CPoseGraph g = sim.graph;
	const double before = rmsPositionError(g, sim.groundTruth);
	const TOptimizationReport rep = CPoseGraphOptimizer().optimize(g, 0);
	const double after = rmsPositionError(g, sim.groundTruth);
	EXPECT_TRUE(rep.converged);
	EXPECT_LT(rep.finalChi2, rep.initialChi2);
	// chi2 of a correct solution is about the degrees of freedom, 3 (links - nodes + 1).
	const double dof = 3.0 * (double(g.numLinks()) - 2999.0);
	EXPECT_LT(rep.finalChi2, 1.3 * dof) << "dof " << dof;
	EXPECT_TRUE(rep.downweightedLinks.empty()) << rep.downweightedLinks.size();
	EXPECT_LT(after, 0.2 * before) << "rms before " << before << " after " << after;
	// The least-squares optimum is statistically consistent (chi2 ~ dof above) but not the
	// truth: compare with it instead.
	TPoseGraphOptimizerParams plain;
	plain.robust_loop_closures = false;
	CPoseGraph ls = sim.graph;
	CPoseGraphOptimizer(plain).optimize(ls, 0);
	EXPECT_LT(rmsPositionError(g, ls.poses()), 0.05);
}

TEST(PoseGraphOptimizer, AnchorStaysAndUnreachedNodesAreUntouched)
{
	auto sim = simulateManhattanPoseGraph(200, 5, 0.05, 0.01, 5);
	CPoseGraph g = sim.graph;
	const size_t island = g.addNode({100, 100, 1});  // no links
	const TPose2D anchorBefore = g.pose(50);
	const TOptimizationReport rep = CPoseGraphOptimizer().optimize(g, 50);
	EXPECT_EQ(rep.numFreeNodes, 199u);
	EXPECT_EQ(g.pose(50).x, anchorBefore.x);
	EXPECT_EQ(g.pose(island).x, 100.0);
	EXPECT_THROW(CPoseGraphOptimizer().optimize(g, 9999), std::exception);
}

TEST(PoseGraphOptimizer, WindowMovesOnlyFreeNodesAndFindsTheirOptimum)
{
	const auto sim = simulateManhattanPoseGraph(400, 8, 0.05, 0.01, 21);
	CPoseGraph g = sim.graph;
	// Converged tightly (the default stops at a 1e-4 relative cost decrease, about 2e-6 m
	// from the optimum here), so that both solves land on the same optimum to 1e-6.
	TPoseGraphOptimizerParams tight;
	tight.relative_cost_tolerance = 1e-9;
	const CPoseGraphOptimizer opt(tight);
	opt.optimize(g, 0);
	const CPoseGraph optimum = g;
	// Perturb the last K poses; a window solve with the rest fixed at the optimum must bring
	// them back to the optimum (which also minimises the windowed problem).
	const size_t K = 10, n = g.numNodes();
	std::vector<size_t> window;
	for (size_t i = n - K; i < n; ++i)
	{
		window.push_back(i);
		g.setPose(i, compose(g.pose(i), {0.3, -0.2, 0.1}));
	}
	const CPoseGraph perturbed = g;
	const TOptimizationReport rep = opt.optimizeSubset(g, window);
	EXPECT_EQ(rep.numFreeNodes, K);
	EXPECT_TRUE(rep.converged);
	for (size_t i = 0; i < n - K; ++i)
	{
		EXPECT_EQ(g.pose(i).x, perturbed.pose(i).x);
		EXPECT_EQ(g.pose(i).y, perturbed.pose(i).y);
		EXPECT_EQ(g.pose(i).phi, perturbed.pose(i).phi);
	}
	EXPECT_LT(maxPoseDifference(g, optimum), 1e-6);
	EXPECT_GT(maxPoseDifference(perturbed, optimum), 0.2);
}

TEST(PoseGraphOptimizer, WindowCoveringAllButTheAnchorEqualsFullSolve)
{
	const auto sim = simulateManhattanPoseGraph(300, 7, 0.05, 0.01, 8);
	CPoseGraph full = sim.graph, windowed = sim.graph;
	const CPoseGraphOptimizer opt;
	const auto r1 = opt.optimize(full, 0);
	std::vector<size_t> all;
	for (size_t i = 1; i < windowed.numNodes(); ++i) all.push_back(i);
	std::shuffle(all.begin(), all.end(), std::mt19937(3));  // any order
	const auto r2 = opt.optimizeSubset(windowed, all);
	EXPECT_EQ(r1.numLinks, r2.numLinks);
	EXPECT_NEAR(r1.finalChi2, r2.finalChi2, 1e-6 * r1.finalChi2);
	EXPECT_LT(maxPoseDifference(full, windowed), 1e-6);
}

TEST(PoseGraphOptimizer, WindowRejectsUndeterminedOrBadNodeLists)
{
	CPoseGraph g;
	for (int i = 0; i < 5; ++i) g.addNode({double(i), 0, 0});
	const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
	g.addLink({0, 1, {1, 0, 0}, I, LinkType::Odometry});
	g.addLink({3, 4, {1, 0, 0}, I, LinkType::Odometry});
	const CPoseGraphOptimizer opt;
	EXPECT_THROW(opt.optimizeSubset(g, {3, 4}), std::exception);  // no fixed neighbour
	EXPECT_THROW(opt.optimizeSubset(g, {2}), std::exception);     // no link at all
	EXPECT_THROW(opt.optimizeSubset(g, {1, 1}), std::exception);  // duplicate
	EXPECT_THROW(opt.optimizeSubset(g, {7}), std::exception);     // out of range
	EXPECT_NO_THROW(opt.optimizeSubset(g, {1}));
	EXPECT_EQ(opt.optimizeSubset(g, {}).numFreeNodes, 0u);
}

// ----------------------------------------------------------------- MRPT reference optimiser
namespace
{
/** Reads a TORO file (VERTEX2 id x y phi / EDGE2 from to dx dy dphi Ixx Ixy Iyy Ipp Ixp Iyp).
 * MRPT's own reader takes EDGE2 information in g2o order, which makes this file's
 * information matrices indefinite (mrpt-notes.md), so the test reads it itself. */
CPoseGraph readToro(const std::string& path)
{
	std::ifstream f(path);
	CPoseGraph g;
	std::string line;
	while (std::getline(f, line))
	{
		std::istringstream s(line);
		std::string tag;
		s >> tag;
		if (tag == "VERTEX2")
		{
			size_t id;
			TPose2D p;
			s >> id >> p.x >> p.y >> p.phi;
			EXPECT_EQ(id, g.numNodes());
			g.addNode(p);
		}
		else if (tag == "EDGE2")
		{
			TLink l;
			double xx, xy, yy, pp, xp, yp;
			s >> l.from >> l.to >> l.toInFrom.x >> l.toInFrom.y >> l.toInFrom.phi >> xx >> xy >>
				yy >> pp >> xp >> yp;
			l.information << xx, xy, xp, xy, yy, yp, xp, yp, pp;
			l.type = l.to == l.from + 1 ? LinkType::Odometry : LinkType::LoopClosure;
			g.addLink(l);
		}
	}
	return g;
}
}  // namespace

TEST(PoseGraphOptimizer, ReachesMrptLevMarqChi2OnCircle50)
{
	const std::string in = "/usr/share/mrpt/datasets/graph_2d_circle_50nodes.graph";
	const std::string truthFile =
		"/usr/share/mrpt/datasets/graph_2d_circle_50nodes_groundtruth.graph";
	LRGC_SKIP_IF_MISSING(in);
	LRGC_SKIP_IF_MISSING(truthFile);
	if (std::system("command -v graph-slam >/dev/null 2>&1") != 0)
		GTEST_SKIP() << "MRPT's graph-slam program is not installed";
	const CPoseGraph start = readToro(in);
	const CPoseGraph truth = readToro(truthFile);
	ASSERT_EQ(start.numNodes(), 50u);

	// MRPT's Levenberg-Marquardt on the same problem, written by us as EDGE_SE2.
	const std::string dir = lrgc::test::makeTempDir("posegraph_mrpt_reference");
	toMrpt(start).saveToTextFile(dir + "/in.graph");
	const std::string cmd = "graph-slam --2d --levmarq --max-iters 100 -q -i " + dir +
							"/in.graph -o " + dir + "/out.graph </dev/null >" + dir +
							"/log.txt 2>&1";
	ASSERT_EQ(std::system(cmd.c_str()), 0) << "see " << dir << "/log.txt";
	mrpt::graphs::CNetworkOfPoses2DInf mrptOut;
	mrptOut.loadFromTextFile(dir + "/out.graph");
	CPoseGraph theirs = start;
	ASSERT_EQ(mrptOut.nodes.size(), 50u);
	for (const auto& [id, p] : mrptOut.nodes) theirs.setPose(id, {p.x(), p.y(), p.phi()});

	// Ours on the same graph, all links unrobustified (a least-squares comparison), fixed
	// at node 0 as MRPT's root.
	TPoseGraphOptimizerParams params;
	params.robust_loop_closures = false;
	CPoseGraph ours = start;
	const TOptimizationReport rep = CPoseGraphOptimizer(params).optimize(ours, 0);
	const double chi2Ours = totalChi2(ours), chi2Theirs = totalChi2(theirs);
	EXPECT_TRUE(rep.converged);
	EXPECT_NEAR(rep.finalChi2, chi2Ours, 1e-9 * chi2Ours);
	EXPECT_LE(chi2Ours, chi2Theirs * (1 + 1e-6))
		<< "ours " << chi2Ours << " MRPT " << chi2Theirs;
	EXPECT_LT(chi2Ours, 0.01 * totalChi2(start));
	// Ours is as close to truth as MRPT's, each expressed relative to its node 0 (MRPT's
	// output is in another gauge).
	const auto err = [&](const CPoseGraph& g)
	{
		double s = 0;
		for (size_t i = 0; i < 50; ++i)
		{
			const TPose2D p = compose(truth.pose(0), between(g.pose(0), g.pose(i)));
			s += std::hypot(p.x - truth.pose(i).x, p.y - truth.pose(i).y);
		}
		return s / 50;
	};
	EXPECT_LE(err(ours), err(theirs) + 1e-3);
	EXPECT_LT(err(ours), 0.5 * err(start));
	std::cout << "circle50: chi2 start " << totalChi2(start) << ", MRPT levmarq " << chi2Theirs
			  << ", ours " << chi2Ours << " (" << rep.iterations
			  << " iterations); mean position "
			  << "error vs truth: start " << err(start) << " m, MRPT " << err(theirs)
			  << " m, ours " << err(ours) << " m\n";
}

// ----------------------------------------------------------------- false loop closures
