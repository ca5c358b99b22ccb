/* CLocalRegistration on a known graph: keyframes ray-cast from known poses in the synthetic
 * room world, noisy odometry priors, and the window solve of Lu & Milios over the last K
 * poses (paper 2.2). Checked: the window converges to the truth, only the last K poses move,
 * older ones are left bit for bit; the patch link, reused keyframes and the helper thread.
 * A scan's registration from its prior: LocalRegistration_registerScan_unittest.cpp. */
#include <gtest/gtest.h>
#include <lrgc/local_registration/LocalRegistration.h>
#include <lrgc/local_registration/MotionPredictor.h>
#include <lrgc/common/se2.h>

#include <cmath>
#include <random>

#include "LocalRegistration_unittest.h"

using namespace lrgc;
using namespace lrgc::test;
using mrpt::math::TPose2D;

namespace
{
/** Keyframes 0..n-1 of `run` at their true poses, chained by tight scan-match links, entered
 * into `local`'s window in order. */
void enterTrueWindow(const TKnownRun& run, size_t n, CLocalRegistration& local,
					 CPoseGraph& graph, TKeyframes& keyframes)
{
	const auto& truth = run.tr.truePoses;
	for (size_t i = 0; i < n; ++i)
	{
		graph.addNode(truth[i]), keyframes.push_back(run.keyframes[i]);
		local.enterKeyframe(i, false, graph);
		if (i > 0)
			graph.addLink({i - 1, i, between(truth[i - 1], truth[i]),
						   Eigen::Matrix3d::Identity() * 1e4, LinkType::ScanMatch});
	}
}

/** Odometry link k-1 -> k with the builder's odometry noise model. */
TLink odometryLink(const lrgc::test::TTrajectory& tr, size_t k)
{
	const TPose2D inc = tr.odometryIncrements[k - 1];
	return {k - 1, k, inc, CMotionPredictor().odometryCov(inc).inverse(), LinkType::Odometry};
}
}  // namespace

TEST(LocalRegistration, windowConvergesToTruthAndOnlyTheLastKPosesMove)
{
	const TKnownRun run;
	const auto& truth = run.tr.truePoses;
	TStageParams defaults;
	const size_t K = defaults.local.window_size;
	CLocalRegistration local(defaults.local, defaults.matcher, defaults.optimizer);

	// The graph is in the world frame; node 0 (the gauge) sits at its true pose.
	CPoseGraph graph;
	graph.addNode(truth[0]);
	local.enterKeyframe(0, false, graph);
	TKeyframes keyframes{run.keyframes[0]};
	double worstPrior = 0, worstXY = 0, worstPhi = 0;
	for (size_t n = 1; n < truth.size(); ++n)
	{
		// The new node starts at the odometry prior from the current estimate of its
		// predecessor, as the builder would place it before the window solve.
		const TPose2D prior = compose(graph.pose(n - 1), run.tr.odometryIncrements[n - 1]);
		worstPrior = std::max(worstPrior, positionError(truth[n], prior));
		graph.addNode(prior);
		local.enterKeyframe(n, false, graph);
		keyframes.push_back(run.keyframes[n]);
		const std::vector<TPose2D> before = graph.poses();

		const size_t links = local.linkAndOptimize(graph, keyframes, odometryLink(run.tr, n));
		EXPECT_GE(links, 1U) << "node " << n << ": no pairwise scan match in the window";

		const size_t firstFree = n + 1 > K ? n + 1 - K : 1;  // node 0 never moves
		for (size_t i = 0; i < firstFree; ++i)
			ASSERT_TRUE(graph.pose(i).x == before[i].x && graph.pose(i).y == before[i].y &&
						graph.pose(i).phi == before[i].phi)
				<< "node " << i << " is older than the window of node " << n << " but moved";
		for (size_t i = firstFree; i <= n; ++i)
		{
			worstXY = std::max(worstXY, positionError(truth[i], graph.pose(i)));
			worstPhi = std::max(worstPhi, headingError(truth[i], graph.pose(i)));
			EXPECT_LT(positionError(truth[i], graph.pose(i)), kTolXY)
				<< "node " << i << " after " << n;
			EXPECT_LT(headingError(truth[i], graph.pose(i)), kTolPhi)
				<< "node " << i << " after " << n;
		}
	}
	RecordProperty("worst_window_error_m", std::to_string(worstXY));
	RecordProperty("worst_window_error_deg", std::to_string(worstPhi * 180 / M_PI));
	RecordProperty("worst_prior_error_m", std::to_string(worstPrior));
	// The priors were off by much more than the tolerance: the window did the work.
	EXPECT_GT(worstPrior, 3 * kTolXY);
	const auto deadReckoning = run.tr.odometryPoses.back();
	EXPECT_GT(positionError(truth.back(), deadReckoning), 0.5);

	// Knock the last K-1 poses off by up to 15 cm / 4 deg and add one more keyframe: the
	// window solve pulls all K poses back to the truth from the links it already has, and
	// nothing older moves.
	const size_t n0 = graph.numNodes();
	std::mt19937 rng(8);
	std::uniform_real_distribution<double> dxy(-0.15, 0.15), dphi(-0.07, 0.07);
	for (size_t i = n0 + 1 - K; i < n0; ++i)
		graph.setPose(i, compose(graph.pose(i), TPose2D(dxy(rng), dxy(rng), dphi(rng))));
	std::mt19937 scanRng(99);
	const TPose2D extraTruth = compose(truth.back(), TPose2D(0.3, 0, 0));
	TKeyframe extra;
	extra.scan = lrgc::test::simulateScan(run.world, extraTruth, {}, scanRng);
	extra.scanIndex = n0;
	keyframes.push_back(extra);
	const TPose2D step(0.3, 0.02, 0.01);
	graph.addNode(compose(graph.pose(n0 - 1), step));
	local.enterKeyframe(n0, false, graph);
	const std::vector<TPose2D> before = graph.poses();
	local.linkAndOptimize(
		graph, keyframes,
		{n0 - 1, n0, step, CMotionPredictor().odometryCov(step).inverse(), LinkType::Odometry});
	for (size_t i = 0; i + K <= n0; ++i)
		ASSERT_TRUE(graph.pose(i).x == before[i].x && graph.pose(i).y == before[i].y &&
					graph.pose(i).phi == before[i].phi)
			<< "node " << i << " moved";
	for (size_t i = n0 + 1 - K; i <= n0; ++i)
	{
		const TPose2D t = i < n0 ? truth[i] : extraTruth;
		EXPECT_LT(positionError(t, graph.pose(i)), kTolXY) << "window node " << i;
		EXPECT_LT(headingError(t, graph.pose(i)), kTolPhi) << "window node " << i;
	}
}

TEST(LocalRegistration, keyframeRegisteredAgainstThePatchGetsThePatchLink)
{
	// As the builder does it: the keyframe's scan is registered against the window patch
	// (odometry prior), placed at the registered pose, then linked. The patch link
	// (previous -> new, the registration's pose) joins the odometry link and the pairwise
	// links, which are down-weighted by pairwise_link_weight; without an odometry prior
	// there is no patch link and the pairwise links keep their full weight.
	const TKnownRun run;
	const auto& truth = run.tr.truePoses;
	TStageParams p;
	for (const bool fromOdometry : {true, false})
	{
		CLocalRegistration local(p.local, p.matcher, p.optimizer);
		CPoseGraph graph;
		TKeyframes keyframes;
		enterTrueWindow(run, 6, local, graph, keyframes);
		const size_t n = 6;
		lrgc::TMotionPrediction pred;
		pred.motion = compose(run.tr.odometryIncrements[n - 1], TPose2D(0.05, -0.04, 0.03));
		pred.cov = CMotionPredictor().odometryCov(pred.motion);
		pred.fromOdometry = fromOdometry;
		pred.stepSeconds = 0.2;
		const TRegistration reg =
			local.registerScan(graph, keyframes, run.keyframes[n].scan,
							   compose(graph.pose(n - 1), pred.motion), pred);
		ASSERT_TRUE(reg.matched);
		EXPECT_LT(positionError(truth[n], reg.scanInMap), kTolXY);
		graph.addNode(reg.scanInMap);
		local.enterKeyframe(n, false, graph);
		keyframes.push_back(run.keyframes[n]);
		const size_t linksBefore = graph.numLinks();
		local.linkAndOptimize(
			graph, keyframes,
			{n - 1, n, pred.motion, CMotionPredictor().odometryCov(pred.motion).inverse(),
			 LinkType::Odometry});
		// The first link after the odometry one is the patch link, if any.
		const TLink& first = graph.link(linksBefore + 1);
		const TPose2D registered = between(truth[n - 1], reg.scanInMap);
		const bool isPatchLink = first.from == n - 1 && first.to == n &&
								 translationNorm(between(first.toInFrom, registered)) < 1e-9;
		EXPECT_EQ(isPatchLink, fromOdometry);
		// Pairwise links: information scaled by pairwise_link_weight with the patch link.
		double maxPairwiseInfo = 0;
		for (size_t id = linksBefore + 1 + (fromOdometry ? 1 : 0); id < graph.numLinks(); ++id)
			maxPairwiseInfo = std::max(maxPairwiseInfo, graph.link(id).information(2, 2));
		const double floorPhiInfo = 1 / std::pow(p.local.link_noise.floor_phi, 2);
		if (fromOdometry)
			EXPECT_LT(maxPairwiseInfo, p.local.pairwise_link_weight * floorPhiInfo * 1.0001);
		else
			EXPECT_GT(maxPairwiseInfo, p.local.pairwise_link_weight * floorPhiInfo * 1.0001);
		EXPECT_LT(positionError(truth[n], graph.pose(n)), kTolXY);
		EXPECT_LT(headingError(truth[n], graph.pose(n)), kTolPhi);
	}
}

TEST(LocalRegistration, aReusedKeyframeAnchorsThePatchAndIsHeldFixed)
{
	// A window of keyframes 0..5 at their true poses; the robot comes back to keyframe 2
	// (CKeyframeReuse): it becomes the window's anchor, the scans are registered in its frame,
	// and the window solve of the next new keyframe moves that one only.
	const TKnownRun run;
	const auto& truth = run.tr.truePoses;
	TStageParams p;
	CLocalRegistration local(p.local, p.matcher, p.optimizer);
	CPoseGraph graph;
	TKeyframes keyframes;
	enterTrueWindow(run, 6, local, graph, keyframes);
	local.enterKeyframe(2, true, graph);
	ASSERT_EQ(local.anchor(), std::optional<size_t>(2));
	EXPECT_EQ(local.window().size(), 6U);  // 2 moved to the newest end, not doubled

	lrgc::TMotionPrediction pred;
	pred.motion = TPose2D(0.05, 0, 0);
	pred.cov = CMotionPredictor().odometryCov(TPose2D(0.3, 0, 0));
	pred.fromOdometry = true;
	pred.stepSeconds = 0.2;
	const TPose2D prior = compose(truth[6], TPose2D(0.04, -0.03, 0.02));
	const TRegistration reg =
		local.registerScan(graph, keyframes, run.keyframes[6].scan, prior, pred);
	ASSERT_TRUE(reg.matched);
	EXPECT_LT(positionError(truth[6], reg.scanInMap), kTolXY);

	graph.addNode(reg.scanInMap), keyframes.push_back(run.keyframes[6]);
	local.enterKeyframe(6, false, graph);
	const std::vector<TPose2D> before = graph.poses();
	const TPose2D odo = between(truth[2], truth[6]);
	local.linkAndOptimize(
		graph, keyframes,
		{2, 6, odo, CMotionPredictor().odometryCov(odo).inverse(), LinkType::Odometry});
	for (size_t i = 0; i < 6; ++i)
		EXPECT_TRUE(graph.pose(i).x == before[i].x && graph.pose(i).y == before[i].y &&
					graph.pose(i).phi == before[i].phi)
			<< "keyframe " << i << " belongs to the map but moved";
	// The patch link comes from the anchor, keyframe 2 (links: 5 chain, odometry, patch).
	ASSERT_GT(graph.numLinks(), 6U);
	const TLink& patch = graph.link(6);
	EXPECT_EQ(patch.from, 2U);
	EXPECT_EQ(patch.to, 6U);
	EXPECT_LT(positionError(truth[6], graph.pose(6)), kTolXY);
	EXPECT_LT(headingError(truth[6], graph.pose(6)), kTolPhi);
}

TEST(LocalRegistration, helperThreadLeavesEveryResultBitForBit)
{
	// The builder's sequence for each keyframe (register against the patch, add the node,
	// link and solve the window), with the helper thread preparing the next patch and sharing
	// the pairwise matches. Each step is repeated by a fresh CLocalRegistration without a
	// helper on a copy of the graph (it builds every cloud itself, in order): registrations
	// and graphs must be equal bit for bit. Midway the window is moved as a loop closure
	// would (after the helper built the patch from the old poses): that patch must not be
	// used.
	const TKnownRun run;
	TStageParams p;
	CLocalRegistration local(p.local, p.matcher, p.optimizer);
	CPoseGraph graph;
	graph.addNode(run.tr.truePoses[0]);
	local.enterKeyframe(0, false, graph);
	TKeyframes keyframes{run.keyframes[0]};
	auto same = [](const TPose2D& a, const TPose2D& b)
	{ return a.x == b.x && a.y == b.y && a.phi == b.phi; };
	auto sameLinks = [&](const CPoseGraph& a, const CPoseGraph& b)
	{
		if (a.numLinks() != b.numLinks()) return false;
		for (size_t id = 0; id < a.numLinks(); ++id)
			if (a.link(id).from != b.link(id).from || a.link(id).to != b.link(id).to ||
				!same(a.link(id).toInFrom, b.link(id).toInFrom) ||
				a.link(id).information != b.link(id).information)
				return false;
		return true;
	};
	size_t moved = 0;
	for (size_t n = 1; n < run.tr.truePoses.size(); ++n)
	{
		if (n == 12)
		{  // X_i <- C (+) X_i for the newest nodes, as CLoopClosing carries them along
		   // (carriedAlong)
			const TPose2D C(0.04, -0.03, 0.02);
			for (size_t i = 5; i < n; ++i) graph.setPose(i, compose(C, graph.pose(i)));
			local.invalidate();
			moved = n;
		}
		lrgc::TMotionPrediction pred;
		pred.motion = run.tr.odometryIncrements[n - 1];
		pred.cov = CMotionPredictor().odometryCov(pred.motion);
		pred.fromOdometry = true;
		pred.stepSeconds = 0.2;
		const TPose2D prior = compose(graph.pose(n - 1), pred.motion);
		const TScan2D& scan = run.keyframes[n].scan;

		CLocalRegistration ref(p.local, p.matcher, p.optimizer, false);
		CPoseGraph refGraph = graph;
		for (const size_t node : local.window()) ref.enterKeyframe(node, false, refGraph);
		const TRegistration refReg = ref.registerScan(refGraph, keyframes, scan, prior, pred);
		const TRegistration reg = local.registerScan(graph, keyframes, scan, prior, pred);
		ASSERT_TRUE(same(reg.scanInMap, refReg.scanInMap) &&
					reg.cov.get() == refReg.cov.get() && reg.matched == refReg.matched)
			<< "keyframe " << n << ": registration differs from a fresh one";

		keyframes.push_back(run.keyframes[n]);
		graph.addNode(reg.scanInMap);
		refGraph.addNode(refReg.scanInMap);
		local.enterKeyframe(n, false, graph);
		ref.enterKeyframe(n, false, refGraph);
		local.linkAndOptimize(graph, keyframes, odometryLink(run.tr, n));
		ref.linkAndOptimize(refGraph, keyframes, odometryLink(run.tr, n));
		ASSERT_TRUE(sameLinks(graph, refGraph)) << "keyframe " << n << ": links differ";
		for (size_t i = 0; i <= n; ++i)
			ASSERT_TRUE(same(graph.pose(i), refGraph.pose(i)))
				<< "keyframe " << n << ": node " << i << " differs";
	}
	EXPECT_EQ(moved, 12U);
	EXPECT_GT(graph.numLinks(), 3 * graph.numNodes());  // pairwise links were made
}

/* lonePatchLinkCov: points 0.6 m apart with normal_radius_m 0.15 m scale x and y by 4 (their
 * variances by 16, their correlation kept) and leave the heading's variance as it was; a scan
 * whose points lie closer than the radius keeps its covariance bit for bit. */
TEST(LocalRegistration, lonePatchLinkCovWidensOnlyWhereReturnsAreSparse)
{
	Eigen::Matrix3d cov;
	cov << 4e-4, 1e-4, 2e-5, 1e-4, 2e-4, -1e-5, 2e-5, -1e-5, 3e-5;
	TScan2D sparse, dense;
	for (int i = 0; i < 50; ++i)
	{
		sparse.points.emplace_back(40.0, 0.6 * i);
		dense.points.emplace_back(4.0, 0.05 * i);
	}
	const Eigen::Matrix3d w = lonePatchLinkCov(cov, sparse, 0.15);
	EXPECT_NEAR(w(0, 0), 16 * cov(0, 0), 1e-12);
	EXPECT_NEAR(w(1, 1), 16 * cov(1, 1), 1e-12);
	EXPECT_NEAR(w(0, 1), 16 * cov(0, 1), 1e-12);
	EXPECT_NEAR(w(0, 2), 4 * cov(0, 2), 1e-12);
	EXPECT_EQ(w(2, 2), cov(2, 2));
	EXPECT_EQ(lonePatchLinkCov(cov, dense, 0.15), cov);
}

TEST(LocalRegistration, aKeyframeWhosePatchMatchFailedIsPlacedFromItsPairwiseMatchesBasin)
{
	// The keyframe's patch match failed (sparse MIT-CSAIL 25: from odometry 21 deg short of
	// the turn it converged 15 deg the other way, rms 0.104 m > 0.1; here the registration
	// is given no returns) and it enters the window at its prior, 0.3 m and 12 deg off. Its
	// pairwise matches agree on the true pose; the patch match started there passes, so the
	// keyframe gets its patch link (the pairwise links then down-weighted by
	// pairwise_link_weight) and stands where the patch puts it.
	const TKnownRun run;
	const auto& truth = run.tr.truePoses;
	TStageParams p;
	CLocalRegistration local(p.local, p.matcher, p.optimizer, false);
	CPoseGraph graph;
	TKeyframes keyframes;
	const size_t n = 8;
	enterTrueWindow(run, n, local, graph, keyframes);
	lrgc::TMotionPrediction pred;
	pred.motion =
		compose(between(truth[n - 1], truth[n]), TPose2D(0.1, 0.25, -12 * M_PI / 180));
	pred.cov = CMotionPredictor().odometryCov(pred.motion);
	pred.fromOdometry = true;
	pred.stepSeconds = 0.2;
	const TPose2D prior = compose(graph.pose(n - 1), pred.motion);
	const TRegistration reg = local.registerScan(graph, keyframes, TScan2D{}, prior, pred);
	ASSERT_FALSE(reg.matched);
	graph.addNode(reg.scanInMap);
	local.enterKeyframe(n, false, graph, false);
	keyframes.push_back(run.keyframes[n]);
	const size_t linksBefore = graph.numLinks();
	local.linkAndOptimize(graph, keyframes,
						  {n - 1, n, pred.motion, pred.cov.inverse(), LinkType::Odometry});
	EXPECT_EQ(local.keyframesReseeded(), 1u);
	ASSERT_GE(graph.numLinks(), linksBefore + 3);  // odometry, patch link, pairwise links
	const TLink& patchLink = graph.link(linksBefore + 1);
	EXPECT_EQ(patchLink.from, n - 1);
	EXPECT_LT(positionError(between(truth[n - 1], truth[n]), patchLink.toInFrom), kTolXY);
	const double floorPhiInfo = 1 / std::pow(p.local.link_noise.floor_phi, 2);
	for (size_t id = linksBefore + 2; id < graph.numLinks(); ++id)
		EXPECT_LT(graph.link(id).information(2, 2),
				  p.local.pairwise_link_weight * floorPhiInfo * 1.0001);
	EXPECT_LT(positionError(truth[n], graph.pose(n)), kTolXY);
	EXPECT_LT(headingError(truth[n], graph.pose(n)), 0.2 * M_PI / 180);
}
