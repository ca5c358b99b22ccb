/* Relation metric (Kuemmerle et al. 2009) on hand-computed cases: identity, translation,
 * rotation, the order of the error transform, wrap at +-pi, interpolated endpoints, the
 * Intel-like non-monotonic trajectory, unmatched relations, statistics, malformed files. */
#include <gtest/gtest.h>
#include <lrgc_apps/eval/relation_metric.h>
#include <mrpt/core/exceptions.h>
#include <test_data.h>

#include <cmath>
#include <string>

using namespace lrgc::apps::eval;
using mrpt::math::TPose2D;

namespace
{
constexpr double kDeg = M_PI / 180.0;

CTrajectory2D trajectory(std::vector<std::pair<double, TPose2D>> tp)
{
	std::vector<TTimedPose2D> poses;
	for (const auto& [t, p] : tp) poses.push_back({t, p, 0});
	return CTrajectory2D(std::move(poses));
}

TRelation relation(double t1, double t2, double x, double y, double phi)
{
	TRelation r;
	r.t1 = t1, r.t2 = t2, r.motion = {x, y, phi};
	return r;
}

TRelationEvaluation evalOne(const TPose2D& a, const TPose2D& b, const TPose2D& rel)
{
	return evaluateRelations(trajectory({{1.0, a}, {2.0, b}}),
							 {relation(1.0, 2.0, rel.x, rel.y, rel.phi)});
}
}  // namespace

TEST(RelationMetric, IdentityGivesZeroError)
{
	const auto ev = evalOne({1, 2, 90 * kDeg}, {1, 3, 90 * kDeg}, {1, 0, 0});
	ASSERT_EQ(ev.errors.size(), 1u);
	EXPECT_NEAR(ev.errors[0].trans_m, 0, 1e-12);
	EXPECT_NEAR(ev.errors[0].rot_deg, 0, 1e-12);
	EXPECT_TRUE(ev.unmatched.empty());
}

TEST(RelationMetric, PureTranslation)
{
	// Estimated motion (1, 0, 0), true (0.9, 0, 0): e = (0.1, 0, 0).
	const auto ev = evalOne({0, 0, 0}, {1, 0, 0}, {0.9, 0, 0});
	EXPECT_NEAR(ev.errors[0].trans_m, 0.1, 1e-12);
	EXPECT_NEAR(ev.errors[0].rot_deg, 0, 1e-12);
}

TEST(RelationMetric, PureRotation)
{
	const auto ev = evalOne({0, 0, 0}, {0, 0, 30 * kDeg}, {0, 0, 20 * kDeg});
	EXPECT_NEAR(ev.errors[0].trans_m, 0, 1e-12);
	EXPECT_NEAR(ev.errors[0].rot_deg, 10, 1e-9);
}

TEST(RelationMetric, ErrorIsEstimateTimesInverseRelation)
{
	// delta = (1, 0, 0); relation r = (1, 0, 90 deg), r^-1 = (0, 1, -90 deg);
	// e = delta (+) r^-1 = (1, 1, -90 deg): |t| = sqrt(2), |rot| = 90 deg.
	// (The other order, r^-1 (+) delta = (0, 0, -90 deg), would give |t| = 0.)
	const auto e = relationErrorTransform({0, 0, 0}, {1, 0, 0}, {1, 0, 90 * kDeg});
	EXPECT_NEAR(e.x, 1, 1e-12);
	EXPECT_NEAR(e.y, 1, 1e-12);
	EXPECT_NEAR(e.phi, -90 * kDeg, 1e-12);
	const auto ev = evalOne({0, 0, 0}, {1, 0, 0}, {1, 0, 90 * kDeg});
	EXPECT_NEAR(ev.errors[0].trans_m, std::sqrt(2.0), 1e-12);
	EXPECT_NEAR(ev.errors[0].rot_deg, 90, 1e-9);
}

TEST(RelationMetric, MotionIsMeasuredInTheFrameOfTheFirstPose)
{
	// Robot at (5, 5) heading 180 deg moves to (3, 5): 2 m forward in its own frame.
	const auto ev = evalOne({5, 5, M_PI}, {3, 5, M_PI}, {2, 0, 0});
	EXPECT_NEAR(ev.errors[0].trans_m, 0, 1e-12);
	EXPECT_NEAR(ev.errors[0].rot_deg, 0, 1e-9);
}

TEST(RelationMetric, RotationalErrorWrapsAtPlusMinusPi)
{
	// Headings 179 -> -179 deg: a +2 deg turn; against a true +2 deg, zero error (not 358).
	auto ev = evalOne({0, 0, 179 * kDeg}, {0, 0, -179 * kDeg}, {0, 0, 2 * kDeg});
	EXPECT_NEAR(ev.errors[0].rot_deg, 0, 1e-9);
	// Estimated +179 deg, true -179 deg: 358 deg apart, i.e. 2 deg.
	ev = evalOne({0, 0, 0}, {0, 0, 179 * kDeg}, {0, 0, -179 * kDeg});
	EXPECT_NEAR(ev.errors[0].rot_deg, 2, 1e-9);
	// +pi against -pi: the same rotation.
	ev = evalOne({0, 0, 0}, {0, 0, M_PI}, {0, 0, -M_PI});
	EXPECT_NEAR(ev.errors[0].rot_deg, 0, 1e-9);
	// Estimated -pi/2 ... true +pi/2: 180 deg, the largest error there is.
	ev = evalOne({0, 0, 0}, {0, 0, -M_PI / 2}, {0, 0, M_PI / 2});
	EXPECT_NEAR(ev.errors[0].rot_deg, 180, 1e-9);
}

TEST(RelationMetric, InterpolatedEndpoint)
{
	// Poses at t = 0 (0,0,0) and t = 2 (2,0,0); relation from t = 0 to t = 1, true (1,0,0):
	// the pose at t = 1 is interpolated to (1,0,0), zero error.
	const auto tr = trajectory({{0.0, {0, 0, 0}}, {2.0, {2, 0, 0}}});
	const auto ev = evaluateRelations(tr, {relation(0.0, 1.0, 1, 0, 0)});
	ASSERT_EQ(ev.errors.size(), 1u);
	EXPECT_TRUE(ev.errors[0].interpolated);
	EXPECT_EQ(ev.interpolatedCount, 1u);
	EXPECT_NEAR(ev.errors[0].trans_m, 0, 1e-12);
}

TEST(RelationMetric, NonMonotonicTrajectoryUsesExactPoses)
{
	// File order 10, 11, 10.5, 12 (a backward jitter). The relation 10.5 -> 12 must use the
	// pose written at 10.5, (5, 5), not an interpolation between 10 and 11.
	const auto tr = trajectory(
		{{10.0, {0, 0, 0}}, {11.0, {10, 0, 0}}, {10.5, {5, 5, 0}}, {12.0, {20, 0, 0}}});
	const auto ev = evaluateRelations(tr, {relation(10.5, 12.0, 15, -5, 0)});
	ASSERT_EQ(ev.errors.size(), 1u);
	EXPECT_FALSE(ev.errors[0].interpolated);
	EXPECT_NEAR(ev.errors[0].trans_m, 0, 1e-12);
}

TEST(RelationMetric, RelationsOutsideTheTrajectoryAreReported)
{
	const auto tr = trajectory({{10.0, {0, 0, 0}}, {11.0, {1, 0, 0}}, {12.0, {2, 0, 0}}});
	std::vector<TRelation> rels = {relation(10.0, 11.0, 1, 0, 0),
								   relation(9.0, 10.0, 1, 0, 0),     // t1 before the start
								   relation(11.0, 12.0, 0.5, 0, 0),  // matched, error 0.5
								   relation(11.0, 13.0, 1, 0, 0),    // t2 after the end
								   relation(8.0, 13.0, 1, 0, 0)};    // both
	for (std::size_t i = 0; i < rels.size(); ++i) rels[i].line = i + 1;
	const auto ev = evaluateRelations(tr, rels);
	ASSERT_EQ(ev.errors.size(), 2u);
	ASSERT_EQ(ev.unmatched.size(), 3u);
	EXPECT_EQ(ev.unmatched[0].relationIndex, 1u);
	EXPECT_EQ(ev.unmatched[1].relationIndex, 3u);
	EXPECT_EQ(ev.unmatched[2].relationIndex, 4u);
	EXPECT_NE(ev.unmatched[0].reason.find("t1 = 9.000000 outside"), std::string::npos);
	EXPECT_NE(ev.unmatched[1].reason.find("t2 = 13.000000 outside"), std::string::npos);
	EXPECT_NE(ev.unmatched[2].reason.find("t1 = 8.000000 and t2 = 13.000000"),
			  std::string::npos);
	// Statistics over the two matched ones only: errors 0 and 0.5.
	EXPECT_EQ(ev.trans_m.count, 2u);
	EXPECT_NEAR(ev.trans_m.mean, 0.25, 1e-12);
	EXPECT_NEAR(ev.trans_m.stddev, 0.25, 1e-12);
}

TEST(RelationMetric, StatisticsOfErrorsAndSquares)
{
	const auto s = TErrorStats::fromSamples({1, 2, 3, 4});
	EXPECT_EQ(s.count, 4u);
	EXPECT_DOUBLE_EQ(s.mean, 2.5);
	EXPECT_NEAR(s.stddev, std::sqrt(1.25), 1e-12);     // population
	EXPECT_DOUBLE_EQ(s.meanSq, 7.5);                   // (1 + 4 + 9 + 16) / 4
	EXPECT_NEAR(s.stddevSq, std::sqrt(32.25), 1e-12);  // (6.5^2+3.5^2+1.5^2+8.5^2) / 4
	EXPECT_DOUBLE_EQ(s.max, 4);
	EXPECT_NEAR(s.rms(), std::sqrt(7.5), 1e-12);
	EXPECT_EQ(TErrorStats::fromSamples({}).count, 0u);
}

TEST(RelationMetric, ParsesRelationsAndNamesMalformedLines)
{
	const auto rels = parseRelations(
		"1.5 2.5 0.1 0.2 0 0 0 -3.2\n\n1134864645.90321  1134864646.32420 0.3 0 0  0 0 0.2\n",
		"r.relations");
	ASSERT_EQ(rels.size(), 2u);
	EXPECT_DOUBLE_EQ(rels[0].t1, 1.5);
	EXPECT_DOUBLE_EQ(rels[0].motion.y, 0.2);
	EXPECT_NEAR(rels[0].motion.phi, -3.2 + 2 * M_PI, 1e-12);
	EXPECT_EQ(rels[1].line, 3u);
	EXPECT_DOUBLE_EQ(rels[1].t2, 1134864646.32420);

	const auto msg = [](const std::string& text)
	{
		try
		{
			parseRelations(text, "bad.relations");
		}
		catch (const std::exception& e)
		{
			return mrpt::exception_to_str(e);
		}
		return std::string();
	};
	EXPECT_NE(msg("1 2 0 0 0 0 0 0\n1 2 0 0 0 0 0\n").find("bad.relations:2: expected 8"),
			  std::string::npos);
	EXPECT_NE(msg("1 2 0 0 0 0 0 0\n\n1 2 0 0 0 0 0 0 9\n").find("bad.relations:3: expected 8"),
			  std::string::npos);
	EXPECT_NE(msg("1 2 0 0 0 0 0 yaw\n").find("bad.relations:1: 'yaw' is not a finite"),
			  std::string::npos);
	EXPECT_NE(msg("1 2 0 0 0 0 0 inf\n").find("bad.relations:1: 'inf'"), std::string::npos);
	EXPECT_NE(msg("").find("bad.relations: no relation line"), std::string::npos);
}

TEST(RelationMetric, LoadsTheBenchmarkRelationFiles)
{
	const std::string path = lrgc::test::sharedDatasetPath("intel/intel.relations");
	LRGC_SKIP_IF_MISSING(path);
	const auto rels = loadRelations(path);
	EXPECT_EQ(rels.size(), 2984u);
	const std::string mit = lrgc::test::sharedDatasetPath("mit-csail/mit-csail.relations");
	LRGC_SKIP_IF_MISSING(mit);
	EXPECT_EQ(loadRelations(mit).size(), 1172u);
}

// The heading's tail counts only relations under kShortRelation_s apart: the 3 deg errors at
// 9.9 s and 5.1 s count (over 2, not over 5); those 10 s and 30 s apart do not.
TEST(RelationMetric, ShortRelationsHeadingTail)
{
	const auto tr = trajectory({{0, {0, 0, 0}},
								{9.9, {1, 0, 3 * kDeg}},
								{10, {2, 0, 3 * kDeg}},
								{15, {3, 0, 6 * kDeg}},
								{30, {4, 0, 3 * kDeg}}});
	const std::vector<TRelation> rels = {
		{0, 9.9, {1, 0, 0}}, {0, 10, {2, 0, 0}}, {0, 30, {4, 0, 0}}, {9.9, 15, {2, 0, 0}}};
	const auto ev = evaluateRelations(tr, rels);
	ASSERT_EQ(ev.errors.size(), 4u);
	EXPECT_EQ(ev.shortCount, 2u);
	EXPECT_EQ(ev.shortOver2deg, 2u);
	EXPECT_EQ(ev.shortOver5deg, 0u);
	EXPECT_DOUBLE_EQ(ev.shortOver2degShare(), 1.0);
}
