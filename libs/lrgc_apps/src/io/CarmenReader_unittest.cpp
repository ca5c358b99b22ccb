/* CARMEN reader on small logs the tests generate: order, timestamps, beam geometry,
 * odometry, no-returns, and damaged lines (malformed line, NaN, negative, empty scan, time
 * going backwards). The files themselves (gzip, truncation, corruption, FIFO):
 * CarmenReader_files_unittest.cpp. */
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <io_read_all.h>
#include <io_test_files.h>
#include <lrgc/scan_matching/Scan.h>
#include <lrgc/common/se2.h>
#include <lrgc_apps/io/LogReader.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <test_data.h>

#include "CarmenReader_unittest.h"

#include <cmath>

using namespace lrgc::apps;
using namespace lrgc::apps::test;
using lrgc::test::anyContains;
using lrgc::test::contains;
using lrgc::test::readWholeLog;
using mrpt::math::TPose2D;
using mrpt::obs::CObservation2DRangeScan;
using mrpt::obs::CObservationOdometry;

TEST(CarmenReader, YieldsMessagesInFileOrderWithOdometryBeforeEachScan)
{
	const std::string dir = lrgc::test::makeTempDir("carmen_order");
	const std::string path = writeLog(dir, "basic.clf", basicLog());
	const auto r = readWholeLog(path);
	ASSERT_FALSE(r.error) << *r.error;
	EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();

	struct TExpect
	{
		const char* label;
		int line;
		double t;
	};
	const TExpect expected[] = {{"ODOMETRY", 3, kT0},        {"ODOMETRY", 4, kT0 + 0.05},
								{"LASER", 4, kT0 + 0.05},    {"ODOMETRY", 5, kT0 + 0.1},
								{"ODOMETRY", 6, kT0 + 0.12}, {"REAR_LASER", 6, kT0 + 0.12},
								{"ODOMETRY", 7, kT0 + 0.2},  {"LASER", 7, kT0 + 0.2},
								{"ODOMETRY", 8, kT0 + 0.3},  {"LASER", 8, kT0 + 0.3}};
	ASSERT_EQ(r.entries.size(), std::size(expected));
	for (size_t i = 0; i < r.entries.size(); ++i)
	{
		const TLogEntry& e = r.entries[i];
		ASSERT_TRUE(e.observation) << i;
		EXPECT_FALSE(e.actions);
		EXPECT_FALSE(e.observations);
		EXPECT_EQ(e.observation->sensorLabel, expected[i].label) << i;
		EXPECT_EQ(e.where, path + ": line " + std::to_string(expected[i].line));
		// Timestamps kept as recorded (1e-6 s round trip through mrpt::Clock).
		EXPECT_NEAR(mrpt::Clock::toDouble(e.observation->timestamp), expected[i].t, 1e-6) << i;
	}
	EXPECT_EQ(r.stats.scans, 4u);
	EXPECT_EQ(r.stats.odometry, 6u);
	EXPECT_EQ(r.stats.entries, 10u);
	EXPECT_EQ(r.stats.ignoredLines, 2u);
	EXPECT_EQ(r.stats.noReturnRanges, 0u);
}

// Issue 30: a UTF-8 byte order mark before the first comment made the log "no CARMEN log
// (line 1 starts with '#')"; it is read as the same log without it.
TEST(CarmenReader, ReadsALogThatStartsWithAUtf8ByteOrderMark)
{
	const std::string dir = lrgc::test::makeTempDir("carmen_bom");
	const auto plain = readWholeLog(writeLog(dir, "plain.clf", basicLog()));
	const auto bom = readWholeLog(writeLog(dir, "bom.clf", "\xEF\xBB\xBF" + basicLog()));
	ASSERT_FALSE(bom.error) << *bom.error;
	EXPECT_TRUE(bom.warnings.empty()) << bom.warnings.front();
	EXPECT_EQ(bom.entries.size(), plain.entries.size());
	EXPECT_EQ(bom.stats.scans, plain.stats.scans);
	EXPECT_EQ(bom.stats.ignoredLines, plain.stats.ignoredLines);
}

TEST(CarmenReader, TakesEachScansOdometryFromItsOwnLine)
{
	const std::string dir = lrgc::test::makeTempDir("carmen_odometry");
	const auto r = readWholeLog(writeLog(dir, "basic.clf", basicLog()));
	ASSERT_FALSE(r.error);
	// Entry 1 is the odometry of the FLASER at line 4 (robot1), not the ODOM of line 3.
	const auto odo = as<CObservationOdometry>(r.entries[1]);
	ASSERT_TRUE(odo);
	EXPECT_NEAR(odo->odometry.x(), 2.0, 1e-9);
	EXPECT_NEAR(odo->odometry.y(), 1.0, 1e-9);
	EXPECT_NEAR(odo->odometry.phi(), 0.5, 1e-9);
	EXPECT_EQ(odo->timestamp, r.entries[2].observation->timestamp);
	// The ODOM line itself: pose and velocities as recorded.
	const auto odom = as<CObservationOdometry>(r.entries[3]);
	ASSERT_TRUE(odom);
	EXPECT_NEAR(odom->odometry.x(), 2.05, 1e-9);
	EXPECT_TRUE(odom->hasVelocities);
	EXPECT_NEAR(odom->velocityLocal.vx, 0.3, 1e-9);
	EXPECT_NEAR(odom->velocityLocal.omega, 0.1, 1e-9);
}

TEST(CarmenReader, PlacesTheLaserOnTheRobotFromTheTwoPosesOfItsLine)
{
	const std::string dir = lrgc::test::makeTempDir("carmen_sensor_pose");
	// FOV 180 deg: the aperture is symmetric, so sensorPose is exactly the line's laser pose
	// (with 179 deg the reader turns it by -0.5 deg to centre the aperture).
	TLogReaderOptions opts;
	opts.carmen_180_beams_fov = M_PI;
	const auto r = readWholeLog(writeLog(dir, "basic.clf", basicLog()), opts);
	ASSERT_FALSE(r.error);
	const auto front = as<CObservation2DRangeScan>(r.entries[2]);
	ASSERT_TRUE(front);
	EXPECT_NEAR(front->sensorPose.x(), 0.3, 1e-5);
	EXPECT_NEAR(front->sensorPose.y(), 0.05, 1e-5);
	const auto rear = as<CObservation2DRangeScan>(r.entries[5]);
	ASSERT_TRUE(rear);
	EXPECT_NEAR(rear->sensorPose.x(), -0.2, 1e-5);
	EXPECT_NEAR(std::abs(rear->sensorPose.yaw()), M_PI, 1e-5);
	// The rear laser's first beam (its right, -90 deg) looks to the robot's left.
	EXPECT_NEAR(beamInRobot(*rear, 0), M_PI / 2, 1e-5);
	EXPECT_TRUE(front->rightToLeft);
}

TEST(CarmenReader, GivesBeamAnglesAsTheDatasetsReadmeExplains)
{
	const std::string dir = lrgc::test::makeTempDir("carmen_beams");
	const std::string path = writeLog(dir, "basic.clf", basicLog());
	const double deg = M_PI / 180;
	{
		TLogReaderOptions opts;
		opts.carmen_180_beams_fov = 180 * deg;  // the other reading: -90 .. +90, step 180/179
		const auto r = readWholeLog(path, opts);
		ASSERT_FALSE(r.error);
		// 180 beams, FOV 180 deg: -90 .. +90, step 180/179 deg.
		const auto s180 = as<CObservation2DRangeScan>(r.entries[2]);
		ASSERT_EQ(s180->getScanSize(), 180u);
		EXPECT_NEAR(beamInRobot(*s180, 0), -90 * deg, 1e-6);
		EXPECT_NEAR(beamInRobot(*s180, 179), 90 * deg, 1e-6);
		EXPECT_NEAR(beamInRobot(*s180, 1) - beamInRobot(*s180, 0), 180.0 / 179 * deg, 1e-6);
		// 361 beams: step 0.5 deg.
		const auto s361 = as<CObservation2DRangeScan>(r.entries[9]);
		ASSERT_EQ(s361->getScanSize(), 361u);
		EXPECT_NEAR(beamInRobot(*s361, 0), -90 * deg, 1e-6);
		EXPECT_NEAR(beamInRobot(*s361, 180), 0, 1e-6);
		EXPECT_NEAR(beamInRobot(*s361, 360), 90 * deg, 1e-6);
		EXPECT_NEAR(beamInRobot(*s361, 1) - beamInRobot(*s361, 0), 0.5 * deg, 1e-6);
		// ROBOTLASER1: its own start angle (-1 rad), resolution (0.01 rad), max range.
		const auto robot = as<CObservation2DRangeScan>(r.entries[7]);
		ASSERT_EQ(robot->getScanSize(), 101u);
		EXPECT_NEAR(beamInRobot(*robot, 0), -1.0, 1e-6);
		EXPECT_NEAR(beamInRobot(*robot, 100), 0.0, 1e-6);
		EXPECT_FLOAT_EQ(robot->maxRange, 30.0f);
		EXPECT_FLOAT_EQ(s180->maxRange, 50.0f);
	}
	{
		const auto r = readWholeLog(path);  // default FOV 179 deg: step 1 deg, -90 .. +89
		const auto s180 = as<CObservation2DRangeScan>(r.entries[2]);
		EXPECT_NEAR(beamInRobot(*s180, 0), -90 * deg, 1e-6);
		EXPECT_NEAR(beamInRobot(*s180, 179), 89 * deg, 1e-6);
		EXPECT_NEAR(beamInRobot(*s180, 90), 0, 1e-6);
		const auto s361 = as<CObservation2DRangeScan>(r.entries[9]);  // unaffected
		EXPECT_NEAR(beamInRobot(*s361, 360), 90 * deg, 1e-6);
	}
}

TEST(CarmenReader, NeverMakesObstaclesOfNoReturns)
{
	const std::string dir = lrgc::test::makeTempDir("carmen_noreturn");
	const TPose2D p{0, 0, 0};
	// Sentinels of the benchmark logs (81.83 Intel, 81.91 MIT, 50 ACES), 80.0, inf, 0, and
	// real readings just under the limit (49.91 is ACES' largest real one).
	const std::vector<double> flaser = {81.83, 50.0, 49.91, 81.91, 80.0, INFINITY, 0, 1.25};
	const std::vector<double> robot = {29.99, 30.0, 35.0, 2.0};
	std::string log = lrgc::test::flaserLine(flaser, p, p, 10.0);
	log += lrgc::test::robotLaser1Line(-0.3, 0.3, 0.1, 30.0, robot, p, p, 10.1);
	const auto r = readWholeLog(writeLog(dir, "noreturn.log", log));
	ASSERT_FALSE(r.error) << *r.error;
	const auto s = as<CObservation2DRangeScan>(r.entries[1]);
	const bool valid[] = {false, false, true, false, false, false, false, true};
	for (size_t i = 0; i < flaser.size(); ++i)
	{
		EXPECT_EQ(s->getScanRangeValidity(i), valid[i]) << "beam " << i;
		if (valid[i])
		{
			EXPECT_FLOAT_EQ(s->getScanRange(i), float(flaser[i]));
		}
	}
	const auto s2 = as<CObservation2DRangeScan>(r.entries[3]);
	EXPECT_TRUE(s2->getScanRangeValidity(0));
	EXPECT_FALSE(s2->getScanRangeValidity(1));
	EXPECT_FALSE(s2->getScanRangeValidity(2));
	EXPECT_TRUE(s2->getScanRangeValidity(3));
	EXPECT_EQ(r.stats.noReturnRanges, 6u + 2u);
	EXPECT_TRUE(r.warnings.empty()) << "no-returns are normal, not problems";
	// What the mapper sees: only the real returns.
	EXPECT_EQ(lrgc::scanFromObservation(*s).points.size(), 2u);
	EXPECT_EQ(lrgc::scanFromObservation(*s2).points.size(), 2u);
}

TEST(CarmenReader, MarksNanAndNegativeRangesInvalidAndSaysWhere)
{
	const std::string dir = lrgc::test::makeTempDir("carmen_nan");
	const TPose2D p{0, 0, 0};
	std::string log = lrgc::test::flaserLine({1, 2, 3}, p, p, 1.0);
	log += lrgc::test::flaserLine({1, NAN, -2.5, 4}, p, p, 2.0);
	const std::string path = writeLog(dir, "nan.clf", log);
	const auto r = readWholeLog(path);
	ASSERT_FALSE(r.error);
	const auto s = as<CObservation2DRangeScan>(r.entries[3]);
	EXPECT_TRUE(s->getScanRangeValidity(0));
	EXPECT_FALSE(s->getScanRangeValidity(1));
	EXPECT_FALSE(s->getScanRangeValidity(2));
	EXPECT_TRUE(s->getScanRangeValidity(3));
	EXPECT_EQ(r.stats.invalidRanges, 2u);
	ASSERT_EQ(r.warnings.size(), 1u);
	EXPECT_TRUE(contains(r.warnings[0], path + ": line 2: FLASER: 2 NaN or negative"))
		<< r.warnings[0];
	EXPECT_EQ(lrgc::scanFromObservation(*s).points.size(), 2u);
}

TEST(CarmenReader, SkipsEmptyScansKeepingTheirOdometry)
{
	const std::string dir = lrgc::test::makeTempDir("carmen_empty");
	const TPose2D p{1, 2, 0.3};
	std::string log = lrgc::test::flaserLine({}, p, p, 1.0);
	log += lrgc::test::flaserLine({5}, p, p, 1.5);
	log += lrgc::test::flaserLine({1, 2}, p, p, 2.0);
	const std::string path = writeLog(dir, "empty.clf", log);
	const auto r = readWholeLog(path);
	ASSERT_FALSE(r.error);
	ASSERT_EQ(r.entries.size(), 4u);  // odometry, odometry, odometry + scan
	EXPECT_TRUE(as<CObservationOdometry>(r.entries[0]));
	EXPECT_TRUE(as<CObservationOdometry>(r.entries[1]));
	EXPECT_TRUE(as<CObservation2DRangeScan>(r.entries[3]));
	EXPECT_EQ(r.stats.emptyScans, 2u);
	EXPECT_EQ(r.stats.scans, 1u);
	ASSERT_EQ(r.warnings.size(), 2u);
	EXPECT_TRUE(contains(r.warnings[0], path + ": line 1: FLASER with 0 reading(s)"));
	EXPECT_TRUE(contains(r.warnings[1], path + ": line 2: FLASER with 1 reading(s)"));
}

TEST(CarmenReader, SkipsMalformedLinesNamingTheirNumbers)
{
	const std::string dir = lrgc::test::makeTempDir("carmen_malformed");
	const TPose2D p{0, 0, 0};
	std::string log = lrgc::test::flaserLine({1, 2}, p, p, 1.0);
	log += "FLASER 3 1.0 2.0 0 0 0 0 0 0 2.0 nohost 2.0\n";  // one reading missing
	log += "ODOM 0 0 zero 0 0 0 2.5 nohost 2.5\n";
	log += "\x01\x02garbage\xff\n";
	log += lrgc::test::flaserLine({1, 2}, p, p, 3.0);
	const std::string path = writeLog(dir, "malformed.clf", log);
	const auto r = readWholeLog(path);
	ASSERT_FALSE(r.error);
	EXPECT_EQ(r.stats.scans, 2u);
	EXPECT_EQ(r.stats.skippedLines, 2u);
	EXPECT_EQ(r.stats.ignoredLines, 1u);  // the garbage line is no message we read
	EXPECT_EQ(r.entries.back().where, path + ": line 5");
	ASSERT_EQ(r.warnings.size(), 2u);
	EXPECT_TRUE(contains(r.warnings[0], path + ": line 2: malformed FLASER"));
	EXPECT_TRUE(contains(r.warnings[1], path + ": line 3: malformed ODOM: pose 'zero'"));
}

TEST(CarmenReader, KeepsFileOrderWhenTimeGoesBackwardsAndCountsTheJumps)
{
	const std::string dir = lrgc::test::makeTempDir("carmen_backwards");
	const TPose2D p{0, 0, 0};
	// 20 scans with lines swapped pairwise (the second line of each pair is older): a
	// reordered copy of a well-ordered log. Also one ODOM going back.
	std::vector<double> times;
	std::string log;
	for (int k = 0; k < 10; ++k)
		for (const int j : {1, 0})
		{
			times.push_back(kT0 + 0.1 * (2 * k + j));
			log += lrgc::test::flaserLine({1, 2, 3}, p, p, times.back());
		}
	log += lrgc::test::odomLine(p, kT0 + 5) + lrgc::test::odomLine(p, kT0 + 4);
	const std::string path = writeLog(dir, "reordered.clf", log);
	const auto r = readWholeLog(path);
	ASSERT_FALSE(r.error);
	std::vector<double> scanTimes;
	for (const auto& e : r.entries)
		if (as<CObservation2DRangeScan>(e))
			scanTimes.push_back(mrpt::Clock::toDouble(e.observation->timestamp));
	ASSERT_EQ(scanTimes.size(), times.size());
	for (size_t i = 0; i < times.size(); ++i) EXPECT_NEAR(scanTimes[i], times[i], 1e-6) << i;
	EXPECT_EQ(r.stats.scanTimeJumpsBack, 10u);
	EXPECT_EQ(r.stats.otherTimeJumpsBack, 1u);
	EXPECT_NEAR(r.stats.largestTimeJumpBack, 1.0, 1e-6);
	// Aggregated: the first five verbatim, the rest counted once at the end.
	ASSERT_EQ(r.warnings.size(), 6u);
	EXPECT_TRUE(contains(r.warnings[0], path + ": line 2: FLASER timestamp"));
	EXPECT_TRUE(
		contains(r.warnings[0], "is 0.100000 s earlier than the previous one (line 1)"));
	EXPECT_TRUE(contains(r.warnings[4], "counted, not listed"));
	EXPECT_TRUE(contains(r.warnings[5], "6 more backward time jumps not listed (11 in all"))
		<< r.warnings[5];
	EXPECT_EQ(r.stats.warnings, 11u);
}
