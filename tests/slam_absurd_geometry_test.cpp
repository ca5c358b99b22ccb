/* End to end: scans with absurd geometry (issue 30) neither crash nor hang lrgc-slam; they are
 * dropped or clipped with a warning, and the rest of the log is mapped.
 *
 * The exact inputs of the issue, made here: a ROBOTLASER1 line with a 1e25 m reading and
 * maximum_range 1e30, one with angular_resolution 1e300 (both in the room log of room_log.h);
 * rawlog scans with a 1e20 m reading, aperture = NaN, sensorPose.x = NaN; a rawlog whose scans
 * all have maxRange = 0. Before: a segfault in CAnchorGrid::buildDense or an endless
 * CAnchorGrid::findCell / nearest. Each run is bounded by timeout(1): 124 means a hang. */
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <functional>
#include <limits>

#include "app_runner.h"
#include "io_test_files.h"
#include "room_log.h"
#include "test_data.h"

using namespace lrgc::test;

namespace
{
const double kNaN = std::numeric_limits<double>::quiet_NaN();

// Range [m] from (x, 3) along `angle` [rad] to the walls of the room [0, 12] x [0, 6].
double rangeInRoom(double x, double angle)
{
	const double c = std::cos(angle), s = std::sin(angle);
	double r = 1e9;
	if (std::abs(c) > 1e-9) r = std::min(r, c > 0 ? (12.0 - x) / c : -x / c);
	if (std::abs(s) > 1e-9) r = std::min(r, 3.0 / std::abs(s));
	return r;
}

// The room as an observations-only rawlog; `spoil` changes scans 20..25.
void writeRoomRawlog(const std::string& path,
					 const std::function<void(mrpt::obs::CObservation2DRangeScan&)>& spoil,
					 bool spoilAll = false)
{
	mrpt::io::CFileGZOutputStream file(path);
	auto out = mrpt::serialization::archiveFrom(file);
	for (int k = 0; k <= 80; ++k)
	{
		const double x = 2.0 + 0.1 * k;
		const auto t = mrpt::Clock::fromDouble(1000.0 + 0.2 * k);
		mrpt::obs::CObservationOdometry odo;
		odo.sensorLabel = "ODOMETRY";
		odo.odometry = mrpt::poses::CPose2D(x, 3.0, 0);
		odo.timestamp = t;
		out << odo;
		mrpt::obs::CObservation2DRangeScan scan;
		scan.sensorLabel = "LASER";
		scan.timestamp = t;
		scan.aperture = static_cast<float>(M_PI);
		scan.maxRange = 80.0f;
		scan.resizeScan(181);
		for (int i = 0; i <= 180; ++i)
			scan.setScanRange(i, static_cast<float>(rangeInRoom(x, (i - 90) * M_PI / 180.0))),
				scan.setScanRangeValidity(i, true);
		if (spoilAll || (k >= 20 && k <= 25)) spoil(scan);
		out << scan;
	}
}

// lrgc-slam on `log`, bounded to 120 s (then SIGKILL 5 s later: a run stuck in a computation
// did not heed SIGTERM before issue 30).
TProcessResult mapBounded(const std::string& log, const std::string& out)
{
	return runProcess("/usr/bin/timeout", {"-k", "5", "120", binaryPath("lrgc-slam"), "--input",
										   log, "--out", out, "--quiet"});
}

void expectMappedWithWarning(const std::string& log, const std::string& warning)
{
	const std::string out = log + ".out";
	const auto r = mapBounded(log, out);
	ASSERT_NE(r.exitCode, 124) << "hung on " << log;
	EXPECT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find(warning), std::string::npos) << r.output;
	EXPECT_TRUE(fileExists(out + "/trajectory.tum")) << r.output;
}

class AbsurdGeometry : public ::testing::Test
{
protected:
	void SetUp() override
	{
		m_dir = makeTempDir("absurd_geometry_" + std::to_string(::getpid()));
	}
	std::string m_dir;
};
}  // namespace

TEST_F(AbsurdGeometry, RawlogFarReadingIsClipped)
{
	writeRoomRawlog(m_dir + "/far.rawlog",
					[](auto& s) { s.setScanRange(40, 1e20f), s.maxRange = 1e30f; });
	expectMappedWithWarning(m_dir + "/far.rawlog", "readings beyond 1000 m ignored");
}

TEST_F(AbsurdGeometry, RawlogNaNApertureIsDropped)
{
	writeRoomRawlog(m_dir + "/aperture.rawlog", [](auto& s) { s.aperture = float(kNaN); });
	expectMappedWithWarning(m_dir + "/aperture.rawlog", "dropped: aperture = nan");
}

TEST_F(AbsurdGeometry, RawlogNaNSensorPoseIsDropped)
{
	writeRoomRawlog(m_dir + "/pose.rawlog", [](auto& s) { s.sensorPose.x(kNaN); });
	expectMappedWithWarning(m_dir + "/pose.rawlog",
							"dropped: sensorPose has a non-finite value");
}

TEST_F(AbsurdGeometry, CarmenFarReadingAndHugeResolution)
{
	std::string log = roomLog();
	std::vector<double> ranges(181, 3.0);
	ranges[90] = 1e25;
	const mrpt::math::TPose2D robot(5.0, 3.0, 0);
	log += robotLaser1Line(-M_PI / 2, M_PI, M_PI / 180, 1e30, ranges, robot, robot, 1020.0);
	log += robotLaser1Line(-M_PI / 2, M_PI, 1e300, 80, std::vector<double>(181, 3.0), robot,
						   robot, 1020.5);
	writeTextFile(m_dir + "/room.clf", log);
	const std::string out = m_dir + "/room.out";
	const auto r = mapBounded(m_dir + "/room.clf", out);
	ASSERT_NE(r.exitCode, 124) << "hung";
	EXPECT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("readings beyond 1000 m ignored"), std::string::npos) << r.output;
	EXPECT_NE(r.output.find("dropped: aperture = inf"), std::string::npos) << r.output;
}

TEST_F(AbsurdGeometry, MaxRangeZeroIsNamedWhenNothingIsMapped)
{
	writeRoomRawlog(
		m_dir + "/zero.rawlog", [](auto& s) { s.maxRange = 0.0f; }, true);
	const auto r = mapBounded(m_dir + "/zero.rawlog", m_dir + "/zero.out");
	EXPECT_EQ(r.exitCode, 1) << r.output;
	EXPECT_NE(r.output.find("nothing to map"), std::string::npos) << r.output;
	EXPECT_NE(r.output.find("maxRange = 0"), std::string::npos) << r.output;
}
