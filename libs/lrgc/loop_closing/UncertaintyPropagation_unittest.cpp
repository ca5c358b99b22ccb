/* propagateUncertainty: analytic chain covariance, loops shrinking uncertainty, limits, and
 * the Mahalanobis gate. */
#include <gtest/gtest.h>
#include <lrgc/loop_closing/UncertaintyPropagation.h>
#include <lrgc/common/se2.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

using namespace lrgc;

namespace
{
constexpr double kStep = 0.5, kSx = 0.02, kSy = 0.03, kSphi = 0.01;  // [m], [m], [m], [rad]

/** Straight chain along x; `reversed` stores every link backwards (to -> from). */
CPoseGraph chain(size_t n, bool reversed)
{
	CPoseGraph g;
	const Eigen::Matrix3d info =
		Eigen::Vector3d(1 / (kSx * kSx), 1 / (kSy * kSy), 1 / (kSphi * kSphi)).asDiagonal();
	for (size_t i = 0; i < n; ++i) g.addNode({kStep * double(i), 0, 0});
	for (size_t i = 0; i + 1 < n; ++i)
	{
		if (!reversed)
			g.addLink({i, i + 1, {kStep, 0, 0}, info, LinkType::Odometry});
		else
		{
			// The covariance of (i+1 <- i) that makes (i <- i+1) have diag(kSx, kSy, kSphi)
			// to first order: C' = J C J^T with J the Jacobian of the inverse at (kStep,0,0).
			Eigen::Matrix3d J;
			J << -1, 0, 0, 0, -1, kStep, 0, 0, -1;
			const Eigen::Matrix3d C =
				Eigen::Vector3d(kSx * kSx, kSy * kSy, kSphi * kSphi).asDiagonal();
			const Eigen::Matrix3d Cinv = J * C * J.transpose();
			g.addLink({i + 1, i, {-kStep, 0, 0}, Cinv.inverse(), LinkType::Odometry});
		}
	}
	return g;
}

/** First-order covariance of pose n of a straight chain of n steps (kStep, 0, 0), each with
 * independent noise diag(kSx^2, kSy^2, kSphi^2):
 *   y_n = sum_m (uy_m + kStep theta_{m-1}),  theta_m = sum_{k<=m} uphi_k, so
 *   var x = n kSx^2,  var phi = n kSphi^2,
 *   var y = n kSy^2 + kStep^2 kSphi^2 sum_{k=1}^{n-1} (n-k)^2 = ... (n-1) n (2n-1) / 6,
 *   cov(y, phi) = kStep kSphi^2 sum_{k=1}^{n-1} (n-k) = kStep kSphi^2 n (n-1) / 2. */
Eigen::Matrix3d analyticChainCov(double n)
{
	Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
	C(0, 0) = n * kSx * kSx;
	C(1, 1) = n * kSy * kSy + kStep * kStep * kSphi * kSphi * (n - 1) * n * (2 * n - 1) / 6;
	C(2, 2) = n * kSphi * kSphi;
	C(1, 2) = C(2, 1) = kStep * kSphi * kSphi * n * (n - 1) / 2;
	return C;
}
}  // namespace

TEST(UncertaintyPropagation, ChainEqualsTheAnalyticSum)
{
	for (bool reversed : {false, true})
	{
		const CPoseGraph g = chain(30, reversed);
		const auto res = propagateUncertainty(g, 0);
		ASSERT_EQ(res.size(), 30u);
		EXPECT_EQ(res[0].node, 0u);
		EXPECT_EQ(res[0].cov, Eigen::Matrix3d::Zero());
		for (const auto& r : res)
		{
			const Eigen::Matrix3d expected = analyticChainCov(double(r.node));
			EXPECT_LT((r.cov - expected).cwiseAbs().maxCoeff(), 1e-12 + 1e-9 * expected.norm())
				<< "node " << r.node << (reversed ? " reversed" : "");
			EXPECT_NEAR(r.nodeInSource.x, kStep * double(r.node), 1e-12);
		}
		for (size_t k = 1; k < res.size(); ++k)  // order of increasing position variance
			EXPECT_GE(res[k].cov(0, 0) + res[k].cov(1, 1),
					  res[k - 1].cov(0, 0) + res[k - 1].cov(1, 1));
	}
}

TEST(UncertaintyPropagation, FromTheEndOfTheChainTheLeverArmsShift)
{
	// Seen from the last node (m = n - 1 steps away from node 0): the same variances of x
	// and phi. The heading noise of link k -> k+1 turns the pose of node k+1, so its lever
	// arm is (m - k - 1) steps forward but (k + 1) steps backward:
	//   var y = m kSy^2 + kStep^2 kSphi^2 sum_{j=1}^{m} j^2 = ... m (m+1) (2m+1) / 6.
	const size_t n = 20;
	const double m = double(n - 1);
	const CPoseGraph g = chain(n, false);
	const auto res = propagateUncertainty(g, n - 1);
	const auto it = std::find_if(res.begin(), res.end(), [](auto& r) { return r.node == 0; });
	ASSERT_NE(it, res.end());
	const Eigen::Matrix3d fwd = analyticChainCov(double(n - 1));
	EXPECT_NEAR(it->cov(0, 0), fwd(0, 0), 1e-12);
	EXPECT_NEAR(it->cov(2, 2), fwd(2, 2), 1e-12);
	EXPECT_NEAR(it->cov(1, 1),
				m * kSy * kSy + kStep * kStep * kSphi * kSphi * m * (m + 1) * (2 * m + 1) / 6,
				1e-12);
	EXPECT_GT(it->cov(1, 1), fwd(1, 1));
	EXPECT_NEAR(it->nodeInSource.x, -kStep * double(n - 1), 1e-12);
}

TEST(UncertaintyPropagation, ALoopClosureShortensTheMostCertainPath)
{
	CPoseGraph g = chain(40, false);
	const double before = propagateUncertainty(g, 0).back().cov(1, 1);
	const Eigen::Matrix3d info = Eigen::Vector3d(2500, 2500, 10000).asDiagonal();
	g.addLink({0, 39, {kStep * 39, 0, 0}, info, LinkType::LoopClosure});
	const auto res = propagateUncertainty(g, 0);
	const auto it = std::find_if(res.begin(), res.end(), [](auto& r) { return r.node == 39; });
	ASSERT_NE(it, res.end());
	EXPECT_NEAR(it->cov(0, 0), 1.0 / 2500, 1e-12);  // straight through the loop link
	EXPECT_LT(it->cov(1, 1), 0.01 * before);
	// Disabled again, it no longer counts.
	g.setLinkEnabled(g.numLinks() - 1, false);
	EXPECT_NEAR(propagateUncertainty(g, 0).back().cov(1, 1), before, 1e-15);
}

TEST(UncertaintyPropagation, LimitsBoundTheSearch)
{
	const CPoseGraph g = chain(100, false);
	TUncertaintyLimits lim;
	lim.maxNodes = 7;
	EXPECT_EQ(propagateUncertainty(g, 50, lim).size(), 7u);
	lim = {};
	lim.maxPositionStd = std::sqrt(analyticChainCov(10)(0, 0) + analyticChainCov(10)(1, 1));
	const auto res = propagateUncertainty(g, 0, lim);
	// Nodes 0..10 are within the bound; node 11 is reached from 10 but not expanded.
	EXPECT_EQ(res.size(), 12u);
	EXPECT_THROW(propagateUncertainty(g, 100), std::exception);
}

TEST(UncertaintyPropagation, MahalanobisGateUsesThePositionCovariance)
{
	TRelativeUncertainty r;
	r.nodeInSource = {3, 4, 0.2};
	r.cov = Eigen::Vector3d(4, 16, 1).asDiagonal();
	EXPECT_NEAR(positionMahalanobis2(r), 9.0 / 4 + 16.0 / 16, 1e-12);
	r.nodeInSource = {0, 0, 1};
	EXPECT_EQ(positionMahalanobis2(r), 0.0);
	r.nodeInSource = {1, 0, 0};
	r.cov.setZero();
	EXPECT_THROW(positionMahalanobis2(r), std::exception);
}

// The loop closer's gate reuse (gate_reuse_keyframes): on a chain every path from the source
// to node v runs through node a, so propagating from the source and stopping at a, then
// chaining a's own labels, gives the whole propagation (first order, exactly).
TEST(UncertaintyPropagation, ChainingThroughANodeOnEveryPathEqualsTheWholePropagation)
{
	for (const bool reversed : {false, true})
	{
		CPoseGraph g = chain(30, reversed);
		// A bend, so the Jacobians' heading terms matter.
		for (size_t i = 10; i < 30; ++i)
			g.setPose(i, compose({5, 0, 0.4}, {kStep * double(i - 10), 0, 0}));
		const size_t source = 29, anchor = 22;
		TUncertaintyLimits stop;
		stop.stopAtNode = anchor;
		const auto near = propagateUncertainty(g, source, stop);
		ASSERT_FALSE(near.empty());
		EXPECT_EQ(near.back().node, anchor) << "stops once the anchor is reached";
		EXPECT_LT(near.size(), size_t(30));
		const auto whole = propagateUncertainty(g, source);
		const auto fromAnchor = propagateUncertainty(g, anchor);
		for (const auto& r : fromAnchor)
		{
			if (r.node > anchor) continue;  // behind the anchor only
			const TRelativeUncertainty chained = chainUncertainty(near.back(), r);
			const auto it = std::find_if(whole.begin(), whole.end(),
										 [&](const auto& w) { return w.node == r.node; });
			ASSERT_NE(it, whole.end());
			EXPECT_EQ(chained.node, r.node);
			EXPECT_NEAR(chained.nodeInSource.x, it->nodeInSource.x, 1e-9);
			EXPECT_NEAR(chained.nodeInSource.y, it->nodeInSource.y, 1e-9);
			EXPECT_NEAR(chained.nodeInSource.phi, it->nodeInSource.phi, 1e-9);
			EXPECT_LT((chained.cov - it->cov).cwiseAbs().maxCoeff(),
					  1e-9 * (1 + it->cov.norm()))
				<< "node " << r.node << (reversed ? " (links reversed)" : "");
		}
	}
}

// The loop closer's gate (TStepModel, issue 28 item 1): a step between two nodes is walked
// once, with the information of its link types added; of two links of one type only the most
// certain in position counts (they share their scans). Single links (the default) take the
// odometry link here (smaller position variance) and its heading variance with it.
TEST(UncertaintyPropagation, AFusedStepAddsTheInformationOfItsLinkTypes)
{
	const size_t n = 12;
	CPoseGraph g = chain(n, false);  // odometry: (0.02, 0.03) m, 0.01 rad a step
	const Eigen::Matrix3d scan = Eigen::Vector3d(0.05 * 0.05, 0.04 * 0.04, 0.001 * 0.001)
									 .asDiagonal();  // more certain in heading only
	for (size_t i = 0; i + 1 < n; ++i)
	{
		g.addLink({i, i + 1, {kStep, 0, 0}, scan.inverse(), LinkType::ScanMatch});
		g.addLink({i, i + 1, {kStep, 0, 0}, (4 * scan).inverse(), LinkType::ScanMatch});
	}
	const Eigen::Matrix3d odo =
		Eigen::Vector3d(kSx * kSx, kSy * kSy, kSphi * kSphi).asDiagonal();
	const Eigen::Matrix3d fused = (odo.inverse() + scan.inverse()).inverse();
	TStepModel model;
	model.fuseParallelLinks = true;
	const auto single = propagateUncertainty(g, 0);
	const auto both = propagateUncertainty(g, 0, {}, model);
	const auto at = [](const std::vector<TRelativeUncertainty>& res, size_t node)
	{ return *std::find_if(res.begin(), res.end(), [&](auto& r) { return r.node == node; }); };
	EXPECT_LT((at(single, 1).cov - odo).cwiseAbs().maxCoeff(), 1e-15);
	EXPECT_LT((at(both, 1).cov - fused).cwiseAbs().maxCoeff(), 1e-15);
	// Straight on: the fused heading variance adds up step by step, 100 times less than the
	// odometry's, and the lateral variance its lever arms swing with it.
	const double m = double(n - 1);
	EXPECT_NEAR(at(both, n - 1).cov(2, 2), m * fused(2, 2), 1e-15);
	EXPECT_NEAR(at(single, n - 1).cov(2, 2), m * odo(2, 2), 1e-15);
	EXPECT_LT(at(both, n - 1).cov(1, 1), 0.5 * at(single, n - 1).cov(1, 1));
}

// The drift scan matching's covariance does not hold: driftXY [m^2 per m] of position variance
// per metre of each step, in both axes of its frame; the heading is untouched.
TEST(UncertaintyPropagation, DriftAddsPositionVarianceAlongThePath)
{
	const CPoseGraph g = chain(20, false);
	TStepModel model;
	model.driftXY = 5e-4;
	const auto res = propagateUncertainty(g, 0, {}, model);
	for (const auto& r : res)
	{
		const double k = double(r.node);
		Eigen::Matrix3d expected = analyticChainCov(k);
		expected(0, 0) += k * model.driftXY * kStep;
		expected(1, 1) += k * model.driftXY * kStep;
		EXPECT_LT((r.cov - expected).cwiseAbs().maxCoeff(), 1e-12) << "node " << r.node;
	}
}
