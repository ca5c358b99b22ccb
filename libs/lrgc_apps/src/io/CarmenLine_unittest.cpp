#include <gtest/gtest.h>
#include "io/CarmenLine.h"

#include <cmath>
#include <cstdlib>

using lrgc::apps::parseCarmenLine;
using lrgc::apps::TCarmenRecord;
using Kind = TCarmenRecord::Kind;

namespace
{
TCarmenRecord parse(const std::string& line)
{
	TCarmenRecord r;
	parseCarmenLine(line, r);
	return r;
}
}  // namespace

TEST(CarmenLine, ParsesFlaserFieldsAsRecorded)
{
	const auto r = parse(
		"FLASER 3 1.07 81.83 2.5 0.1 0.2 0.3 0.4 0.5 0.6 976052857.337284 nohost "
		"976052857.337290");
	ASSERT_EQ(r.kind, Kind::FrontLaser) << r.problem;
	EXPECT_EQ(r.message, "FLASER");
	ASSERT_EQ(r.laser.ranges.size(), 3u);
	EXPECT_DOUBLE_EQ(r.laser.ranges[1], 81.83);
	EXPECT_DOUBLE_EQ(r.laser.laserPose.x, 0.1);
	EXPECT_DOUBLE_EQ(r.laser.laserPose.phi, 0.3);
	EXPECT_DOUBLE_EQ(r.laser.robotPose.y, 0.5);
	EXPECT_DOUBLE_EQ(r.laser.robotPose.phi, 0.6);
	// The ipc timestamp, bit for bit what strtod gives.
	EXPECT_EQ(r.laser.timestamp, std::strtod("976052857.337284", nullptr));
	EXPECT_FALSE(r.laser.hasOwnGeometry);
}

TEST(CarmenLine, AcceptsMissingHostnameAndLoggerTimestamp)
{
	EXPECT_EQ(parse("FLASER 2 1 2 0 0 0 0 0 0 12.5").kind, Kind::FrontLaser);
	EXPECT_EQ(parse("FLASER 2 1 2 0 0 0 0 0 0 12.5 host").kind, Kind::FrontLaser);
	EXPECT_EQ(parse("FLASER 2 1 2 0 0 0 0 0 0 12.5 host 12.5\r").kind, Kind::FrontLaser);
	EXPECT_EQ(parse("RLASER 2 1 2 0 0 3.14 0 0 0 12.5 host 12.5").kind, Kind::RearLaser);
}

TEST(CarmenLine, ParsesRobotLaser1WithItsOwnGeometry)
{
	const auto r = parse(
		"ROBOTLASER1 0 -1.5 3.0 0.75 30.0 0.01 0 5 1 2 3 4 30 2 7 8 1 2 0.1 0.9 2 0.1 "
		"0.25 -0.5 0.5 0.3 1.0 100.25 host 100.26");
	ASSERT_EQ(r.kind, Kind::RobotLaser) << r.problem;
	EXPECT_TRUE(r.laser.hasOwnGeometry);
	EXPECT_DOUBLE_EQ(r.laser.startAngle, -1.5);
	EXPECT_DOUBLE_EQ(r.laser.angularResolution, 0.75);
	EXPECT_DOUBLE_EQ(r.laser.maxRange, 30.0);
	ASSERT_EQ(r.laser.ranges.size(), 5u);
	EXPECT_DOUBLE_EQ(r.laser.ranges[4], 30.0);
	EXPECT_DOUBLE_EQ(r.laser.laserPose.x, 1);  // after the 2 remissions
	EXPECT_DOUBLE_EQ(r.laser.robotPose.phi, 0.1);
	EXPECT_DOUBLE_EQ(r.laser.tv, 0.25);
	EXPECT_DOUBLE_EQ(r.laser.rv, -0.5);
	EXPECT_DOUBLE_EQ(r.laser.timestamp, 100.25);
}

TEST(CarmenLine, ParsesOdom)
{
	const auto r = parse("ODOM 1.5 -2 0.25 0.3 0.1 0 70.179699 nohost 70.179699");
	ASSERT_EQ(r.kind, Kind::Odometry) << r.problem;
	EXPECT_DOUBLE_EQ(r.odometry.pose.x, 1.5);
	EXPECT_DOUBLE_EQ(r.odometry.pose.y, -2);
	EXPECT_DOUBLE_EQ(r.odometry.pose.phi, 0.25);
	EXPECT_DOUBLE_EQ(r.odometry.tv, 0.3);
	EXPECT_DOUBLE_EQ(r.odometry.timestamp, 70.179699);
}

TEST(CarmenLine, IgnoresCommentsBlankLinesAndOtherMessages)
{
	EXPECT_EQ(parse("# CARMEN Logfile").kind, Kind::Ignored);
	EXPECT_EQ(parse("").kind, Kind::Ignored);
	EXPECT_EQ(parse("   \t\r").kind, Kind::Ignored);
	const auto p = parse("PARAM robot_front_laser_max 50.0 nohost 0");
	EXPECT_EQ(p.kind, Kind::Ignored);
	EXPECT_EQ(p.message, "PARAM");
}

TEST(CarmenLine, KeepsNanNegativeAndInfiniteRangesForTheReaderToJudge)
{
	const auto r = parse("FLASER 4 nan -1.5 inf 2 0 0 0 0 0 0 5 h 5");
	ASSERT_EQ(r.kind, Kind::FrontLaser) << r.problem;
	EXPECT_TRUE(std::isnan(r.laser.ranges[0]));
	EXPECT_DOUBLE_EQ(r.laser.ranges[1], -1.5);
	EXPECT_TRUE(std::isinf(r.laser.ranges[2]));
}

TEST(CarmenLine, FlagsMalformedLinesNamingTheProblem)
{
	struct TCase
	{
		const char* line;
		const char* mention;
	};
	const TCase cases[] = {
		{"FLASER", "too few fields"},
		{"FLASER 3 1 2 0 0 0 0 0 0 5 h 5", "is not a number"},  // one reading short
		{"FLASER 2 1 2 0 0 0 0 0 0 5 h 5 extra", "unexpected field"},
		{"FLASER 2 1 2 0 0 0 0 0 5 h 5", "timestamp 'h'"},  // one pose field short
		{"FLASER two 1 2 0 0 0 0 0 0 5", "num_readings"},
		{"FLASER 2.5 1 2 0 0 0 0 0 0 5", "num_readings"},
		{"FLASER -2 1 2 0 0 0 0 0 0 5", "num_readings"},
		{"FLASER 99999999 1 2", "num_readings"},
		{"FLASER 2 1 2x 0 0 0 0 0 0 5", "range reading '2x'"},
		{"FLASER 2 1 2 nan 0 0 0 0 0 5", "laser pose"},
		{"FLASER 2 1 2 0 0 0 0 inf 0 5", "odometry pose"},
		{"FLASER 2 1 2 0 0 0 0 0 0 nan", "timestamp"},
		{"ODOM 1 2 3 0 0 0", "too few fields"},
		{"ODOM 1 2 3 0 0 0 t h 5", "timestamp"},
		{"ODOM 1 2 3 0 0 0 5 h five", "logger_timestamp"},
		{"ROBOTLASER1 0 -1.5 3.0 0 30 0.01 0 2 1 2 0 0 0 0 0 0 0 0 0 0 0 0 5 h 5",
		 "angular_resolution"},
		{"ROBOTLASER1 0 -1.5 3.0 0.1 30 0.01 0 2 1 2 5 0 0 0", "remissions"},
		// Issue 30: a reading too many and no host fields shifted every field after it.
		{"FLASER 2 1 2 3 0 0 0 0 0 0 5", "1 unexpected number after the timestamp"},
		// Issue 30: 1e300 became 0.000000 (MRPT's clock overflows).
		{"FLASER 2 1 2 0 0 0 0 0 0 1e300 h 5", "timestamp '1e300' is out of range"},
		{"ODOM 1 2 3 0 0 0 -1e12", "timestamp '-1e12' is out of range"},
	};
	for (const auto& c : cases)
	{
		const auto r = parse(c.line);
		EXPECT_EQ(r.kind, Kind::Malformed) << c.line;
		EXPECT_NE(r.problem.find(c.mention), std::string::npos)
			<< c.line << " -> " << r.problem;
	}
}

TEST(CarmenLine, ReusesTheRecordBetweenLines)
{
	TCarmenRecord r;
	parseCarmenLine("FLASER 3 1 2 3 0 0 0 0 0 0 5 h 5", r);
	parseCarmenLine("FLASER 1 7 0 0 0 0 0 0 6 h 6", r);
	ASSERT_EQ(r.kind, Kind::FrontLaser);
	ASSERT_EQ(r.laser.ranges.size(), 1u);
	EXPECT_DOUBLE_EQ(r.laser.ranges[0], 7);
	parseCarmenLine("FLASER 1 x 0 0 0 0 0 0 6 h 6", r);
	EXPECT_EQ(r.kind, Kind::Malformed);
	parseCarmenLine("ODOM 1 2 3 0 0 0 5 h 5", r);
	EXPECT_EQ(r.kind, Kind::Odometry);
	EXPECT_TRUE(r.problem.empty());
}
