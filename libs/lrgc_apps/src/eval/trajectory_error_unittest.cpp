/* ATE after best-fit SE(2) alignment and ground-truth relations for the RPE, on hand-computed
 * cases. */
#include <gtest/gtest.h>
#include <lrgc/common/se2.h>
#include <lrgc_apps/eval/trajectory_error.h>

#include <cmath>

using namespace lrgc::apps::eval;
using mrpt::math::TPose2D;

namespace
{
CTrajectory2D trajectory(const std::vector<TPose2D>& poses, double t0 = 0, double dt = 1)
{
	std::vector<TTimedPose2D> out;
	for (std::size_t i = 0; i < poses.size(); ++i)
		out.push_back({t0 + dt * static_cast<double>(i), poses[i], i + 1});
	return CTrajectory2D(std::move(out));
}
}  // namespace

TEST(TrajectoryError, AteIsZeroForARigidlyMovedCopy)
{
	const std::vector<TPose2D> gt = {{0, 0, 0}, {1, 0, 0.3}, {1, 1, 1.6}, {0, 2, 3.1}};
	const TPose2D T = {5, -2, 1.0};  // (estimate frame <- ground-truth frame)
	std::vector<TPose2D> est;
	for (const auto& g : gt) est.push_back(lrgc::compose(T, g));
	const auto ate = evaluateAte(trajectory(est), trajectory(gt));
	EXPECT_EQ(ate.matched, 4u);
	EXPECT_NEAR(ate.trans_m.max, 0, 1e-9);
	EXPECT_NEAR(ate.rot_deg.max, 0, 1e-9);
	// The alignment found is T^-1.
	const TPose2D inv = lrgc::inverse(T);
	EXPECT_NEAR(ate.alignment.x, inv.x, 1e-9);
	EXPECT_NEAR(ate.alignment.y, inv.y, 1e-9);
	EXPECT_NEAR(ate.alignment.phi, inv.phi, 1e-9);
}

TEST(TrajectoryError, AteOfASymmetricDeviation)
{
	// Ground truth (0,0), (2,0); estimate (0,0.1), (2,-0.1). Centred: p' = (-1, 0.1), (1,-0.1)
	// and g' = (-1, 0), (1, 0); the best rotation is atan(0.1), which lays the estimate on the
	// x axis at distance sqrt(1.01) from the centroid: each error is sqrt(1.01) - 1 m.
	const auto ate = evaluateAte(trajectory({{0, 0.1, 0}, {2, -0.1, 0}}),
								 trajectory({{0, 0, 0}, {2, 0, 0}}));
	const double e = std::sqrt(1.01) - 1;
	EXPECT_NEAR(ate.alignment.phi, std::atan(0.1), 1e-12);
	EXPECT_NEAR(ate.trans_m.mean, e, 1e-12);
	EXPECT_NEAR(ate.trans_m.stddev, 0, 1e-12);
	EXPECT_NEAR(ate.trans_m.rms(), e, 1e-12);
	EXPECT_NEAR(ate.rot_deg.mean, std::atan(0.1) * 180 / M_PI, 1e-9);
}

TEST(TrajectoryError, AteReportsGroundTruthOutsideTheEstimate)
{
	// Ground truth at t = 0..4, estimate only over t = 1..3.
	const auto gt = trajectory({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {4, 0, 0}});
	const auto est = trajectory({{1, 0, 0}, {2, 0, 0}, {3, 0, 0}}, 1.0);
	const auto ate = evaluateAte(est, gt);
	EXPECT_EQ(ate.matched, 3u);
	ASSERT_EQ(ate.unmatchedGroundTruth.size(), 2u);
	EXPECT_EQ(ate.unmatchedGroundTruth[0], 0u);
	EXPECT_EQ(ate.unmatchedGroundTruth[1], 4u);
	EXPECT_NEAR(ate.trans_m.max, 0, 1e-12);
	EXPECT_THROW(evaluateAte(trajectory({{0, 0, 0}}, 100.0), gt), std::exception);
}

TEST(TrajectoryError, BestFitRigidWithOnePairIsATranslation)
{
	const auto T = bestFitRigid2D({{1, 2, 0.5}}, {{4, 6, 0}});
	EXPECT_DOUBLE_EQ(T.x, 3);
	EXPECT_DOUBLE_EQ(T.y, 4);
	EXPECT_DOUBLE_EQ(T.phi, 0);
}

TEST(TrajectoryError, RelationsOverStepsAndDistance)
{
	// Straight line along x at 0.4 m spacing, heading +90 deg: motion is sideways (-y) in the
	// robot frame.
	const auto gt = trajectory({{0, 0, M_PI / 2},
								{0.4, 0, M_PI / 2},
								{0.8, 0, M_PI / 2},
								{1.2, 0, M_PI / 2},
								{1.6, 0, M_PI / 2}},
							   100.0, 0.5);
	const auto steps = relationsOverSteps(gt, 1);
	ASSERT_EQ(steps.size(), 4u);
	EXPECT_DOUBLE_EQ(steps[1].t1, 100.5);
	EXPECT_DOUBLE_EQ(steps[1].t2, 101.0);
	EXPECT_NEAR(steps[1].motion.x, 0, 1e-12);
	EXPECT_NEAR(steps[1].motion.y, -0.4, 1e-12);
	EXPECT_EQ(relationsOverSteps(gt, 2).size(), 3u);
	// 1 m: 0 -> 1.2 (index 3) and 0.4 -> 1.6 (index 4); from 0.8 no pose is 1 m further.
	const auto dist = relationsOverDistance(gt, 1.0);
	ASSERT_EQ(dist.size(), 2u);
	EXPECT_DOUBLE_EQ(dist[0].t2, 101.5);
	EXPECT_NEAR(dist[0].motion.y, -1.2, 1e-12);
	EXPECT_DOUBLE_EQ(dist[1].t1, 100.5);
	EXPECT_DOUBLE_EQ(dist[1].t2, 102.0);
}

TEST(TrajectoryError, RpeOfADriftingEstimate)
{
	// Ground truth moves 1 m per step along x; the estimate 1.1 m: every 1-step relation has
	// error 0.1 m, every 2 m one 0.2 m.
	std::vector<TPose2D> gt, est;
	for (int i = 0; i < 6; ++i) gt.push_back({1.0 * i, 0, 0}), est.push_back({1.1 * i, 0, 0});
	const auto g = trajectory(gt), e = trajectory(est);
	const auto step = evaluateRelations(e, relationsOverSteps(g, 1));
	EXPECT_EQ(step.errors.size(), 5u);
	EXPECT_NEAR(step.trans_m.mean, 0.1, 1e-12);
	EXPECT_NEAR(step.trans_m.stddev, 0, 1e-12);
	const auto two = evaluateRelations(e, relationsOverDistance(g, 2.0));
	EXPECT_EQ(two.errors.size(), 4u);
	EXPECT_NEAR(two.trans_m.mean, 0.2, 1e-12);
}
