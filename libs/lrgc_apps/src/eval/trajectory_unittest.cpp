/* CTrajectory2D: parsing (TUM and `t x y phi`), malformed lines named by file and line, and
 * pose look-up by time (exact, interpolated, across +-pi, non-monotonic files). */
#include <gtest/gtest.h>
#include <lrgc_apps/eval/trajectory.h>
#include <mrpt/core/exceptions.h>
#include <error_of.h>

#include <cmath>
#include <string>

using namespace lrgc::apps::eval;
using lrgc::test::errorOf;

namespace
{
constexpr double kRadPerDeg = M_PI / 180.0;

std::string tumLine(double t, double x, double y, double yaw)
{
	char buf[200];
	std::snprintf(buf, sizeof(buf), "%.6f %.6f %.6f 0 0 0 %.12f %.12f\n", t, x, y,
				  std::sin(yaw / 2), std::cos(yaw / 2));
	return buf;
}
}  // namespace

TEST(Trajectory, ParsesTumWithYawFromQuaternionAndComments)
{
	const std::string text = "# t x y z qx qy qz qw\n\n" + tumLine(1.5, 1, 2, 30 * kRadPerDeg) +
							 tumLine(2.5, -1, 0.5, -170 * kRadPerDeg);
	const auto tr = CTrajectory2D::parse(text, "mem.tum");
	ASSERT_EQ(tr.size(), 2u);
	EXPECT_DOUBLE_EQ(tr.poses()[0].t, 1.5);
	EXPECT_DOUBLE_EQ(tr.poses()[0].pose.x, 1);
	EXPECT_DOUBLE_EQ(tr.poses()[0].pose.y, 2);
	EXPECT_NEAR(tr.poses()[0].pose.phi, 30 * kRadPerDeg, 1e-9);
	EXPECT_NEAR(tr.poses()[1].pose.phi, -170 * kRadPerDeg, 1e-9);
	EXPECT_EQ(tr.poses()[0].line, 3u);
	EXPECT_EQ(tr.poses()[1].line, 4u);
}

TEST(Trajectory, ParsesGroundTruthFourColumns)
{
	const auto tr = CTrajectory2D::parse("10.0 1 2 3.0\n11.0 2 3 -3.5\n", "gt.txt");
	ASSERT_EQ(tr.size(), 2u);
	EXPECT_DOUBLE_EQ(tr.poses()[0].pose.phi, 3.0);
	EXPECT_NEAR(tr.poses()[1].pose.phi, -3.5 + 2 * M_PI, 1e-12);  // wrapped into (-pi, pi]
}

TEST(Trajectory, YawFromNonUnitQuaternionAndZeroQuaternion)
{
	// 2 * (0, 0, sin 45deg, cos 45deg): yaw 90 deg once normalised.
	EXPECT_NEAR(*yawFromQuaternion(0, 0, 2 * std::sin(M_PI / 4), 2 * std::cos(M_PI / 4)),
				M_PI / 2, 1e-12);
	EXPECT_FALSE(yawFromQuaternion(0, 0, 0, 0).has_value());
}

TEST(Trajectory, MalformedLinesNameFileAndLine)
{
	EXPECT_NE(errorOf([] { CTrajectory2D::parse("1 2 3 4 5 6 7\n", "a.tum"); })
				  .find("a.tum:1: expected 8 numbers"),
			  std::string::npos);
	EXPECT_NE(
		errorOf([] { CTrajectory2D::parse("# c\n1 0 0 0 0 0 0 1\n2 0 0 0 0 0 0\n", "b.tum"); })
			.find("b.tum:3: expected 8 numbers"),
		std::string::npos);
	EXPECT_NE(errorOf([] { CTrajectory2D::parse("1 0 0 0 0 0 0 1\n2 0 x 0 0 0 0 1\n", "c"); })
				  .find("c:2: 'x' is not a finite number"),
			  std::string::npos);
	EXPECT_NE(errorOf([] { CTrajectory2D::parse("1 0 nan 0\n", "d"); })
				  .find("d:1: 'nan' is not a finite number"),
			  std::string::npos);
	EXPECT_NE(errorOf([] { CTrajectory2D::parse("\n\n1 0 0 0 0 0 0 0\n", "e"); })
				  .find("e:3: zero quaternion"),
			  std::string::npos);
	EXPECT_NE(errorOf([] { CTrajectory2D::parse("# only a comment\n", "f"); })
				  .find("f: no pose line"),
			  std::string::npos);
	EXPECT_NE(errorOf([] { CTrajectory2D::loadFromFile("/nonexistent/x.tum"); })
				  .find("/nonexistent/x.tum: cannot open"),
			  std::string::npos);
}

TEST(Trajectory, ExactTimestampUsesThatPose)
{
	const auto tr = CTrajectory2D::parse("1 0 0 0\n2 1 0 0.5\n3 2 0 1.0\n", "t");
	const auto p = tr.poseAt(2.0);
	ASSERT_TRUE(p);
	EXPECT_EQ(p->how, TPoseLookup::Exact);
	EXPECT_DOUBLE_EQ(p->pose.x, 1);
	EXPECT_DOUBLE_EQ(p->pose.phi, 0.5);
	// Relations written with 5 decimals against a log with 6: within 1e-5 s is "equal".
	const auto q = tr.poseAt(2.000004);
	ASSERT_TRUE(q);
	EXPECT_EQ(q->how, TPoseLookup::Exact);
	EXPECT_DOUBLE_EQ(q->pose.x, 1);
	// Beyond the tolerance: interpolated.
	const auto r = tr.poseAt(2.001);
	ASSERT_TRUE(r);
	EXPECT_EQ(r->how, TPoseLookup::Interpolated);
	EXPECT_NEAR(r->pose.x, 1.001, 1e-12);
}

TEST(Trajectory, InterpolatesLinearlyBetweenNeighbours)
{
	const auto tr = CTrajectory2D::parse("0 0 0 0\n2 2 4 1.5707963267948966\n", "t");
	const auto p = tr.poseAt(0.5);
	ASSERT_TRUE(p);
	EXPECT_EQ(p->how, TPoseLookup::Interpolated);
	EXPECT_NEAR(p->pose.x, 0.5, 1e-12);
	EXPECT_NEAR(p->pose.y, 1.0, 1e-12);
	EXPECT_NEAR(p->pose.phi, 22.5 * kRadPerDeg, 1e-12);
}

TEST(Trajectory, InterpolatesHeadingAcrossPlusMinusPi)
{
	// 170 deg -> -170 deg is a +20 deg turn through 180, not -340 deg through 0.
	const auto tr =
		CTrajectory2D::parse("0 0 0 " + std::to_string(170 * kRadPerDeg) + "\n1 0 0 " +
								 std::to_string(-170 * kRadPerDeg) + "\n",
							 "t");
	EXPECT_NEAR(tr.poseAt(0.25)->pose.phi, 175 * kRadPerDeg, 1e-6);
	EXPECT_NEAR(std::abs(tr.poseAt(0.5)->pose.phi), M_PI, 1e-6);
	EXPECT_NEAR(tr.poseAt(0.75)->pose.phi, -175 * kRadPerDeg, 1e-6);
}

TEST(Trajectory, OutsideTimeSpanGivesNothing)
{
	const auto tr = CTrajectory2D::parse("10 0 0 0\n20 1 0 0\n", "t");
	EXPECT_FALSE(tr.poseAt(9.9));
	EXPECT_FALSE(tr.poseAt(20.1));
	EXPECT_TRUE(tr.poseAt(9.999995));  // within the tolerance of the first stamp
	EXPECT_TRUE(tr.poseAt(20.0));
	EXPECT_DOUBLE_EQ(tr.earliestTime(), 10);
	EXPECT_DOUBLE_EQ(tr.latestTime(), 20);
}

TEST(Trajectory, NonMonotonicFileKeepsFileOrderAndInterpolatesOnSortedTimes)
{
	// Intel-like jitter: the third pose's stamp (10.5) is earlier than the second's (11).
	const auto tr = CTrajectory2D::parse(
		"10.0 0 0 0\n"
		"11.0 10 0 0\n"
		"10.5 5 5 0\n"
		"12.0 20 0 0\n",
		"jitter.txt");
	EXPECT_EQ(tr.backwardTimeJumps(), 1u);
	EXPECT_DOUBLE_EQ(tr.poses()[2].pose.y, 5);  // file order kept
	// Equal stamp: that very pose, not an interpolation between 10 and 11.
	const auto p = tr.poseAt(10.5);
	ASSERT_TRUE(p);
	EXPECT_EQ(p->how, TPoseLookup::Exact);
	EXPECT_DOUBLE_EQ(p->pose.x, 5);
	EXPECT_DOUBLE_EQ(p->pose.y, 5);
	// 10.75: between the temporally nearest poses, 10.5 (5,5) and 11.0 (10,0).
	const auto q = tr.poseAt(10.75);
	ASSERT_TRUE(q);
	EXPECT_NEAR(q->pose.x, 7.5, 1e-12);
	EXPECT_NEAR(q->pose.y, 2.5, 1e-12);
	// 11.5: between 11 (10,0) and 12 (20,0).
	EXPECT_NEAR(tr.poseAt(11.5)->pose.x, 15, 1e-12);
}

TEST(Trajectory, DuplicateStampPrefersFirstInFileOrder)
{
	const auto tr = CTrajectory2D::parse("1 0 0 0\n2 1 0 0\n2 7 0 0\n3 2 0 0\n", "dup");
	EXPECT_DOUBLE_EQ(tr.poseAt(2.0)->pose.x, 1);
}

TEST(Trajectory, UserMessageDropsLocationAndCallStack)
{
	try
	{
		CTrajectory2D::parse("1 2 3\n", "u.tum");
		FAIL() << "no exception";
	}
	catch (const std::exception& e)
	{
		EXPECT_EQ(
			userMessage(e),
			"u.tum:1: expected 8 numbers (TUM: t x y z qx qy qz qw) or 4 numbers (t x y phi), "
			"got 3");
	}
	EXPECT_EQ(userMessage(std::runtime_error("plain")), "plain");
}
