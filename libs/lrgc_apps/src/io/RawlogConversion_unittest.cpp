/* CARMEN (and layout-1 rawlog) to observations-only rawlog: the data read back equal, and
 * MRPT's own rawlog-edit reads the file. */
#include <gtest/gtest.h>
#include <io_read_all.h>
#include <io_test_files.h>
#include <lrgc_apps/io/LogReader.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <test_data.h>

#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <regex>

using namespace lrgc::apps;
using lrgc::test::contains;
using lrgc::test::readWholeLog;
using mrpt::math::TPose2D;
using mrpt::obs::CObservation2DRangeScan;
using mrpt::obs::CObservationOdometry;

namespace
{
// A CARMEN log of every kind of line, with no-returns, NaN, and a backward time jump.
std::string generatedCarmen()
{
	std::string s = "# CARMEN Logfile\nPARAM robot_front_laser_max 50.0 nohost 0\n";
	for (int k = 0; k < 60; ++k)
	{
		const double t = 1200000000.0 + 0.1 * k + (k == 30 ? -0.35 : 0.0);
		const TPose2D robot{0.05 * k, 0.01 * k, 0.02 * k};
		std::vector<double> r(180);
		for (size_t i = 0; i < r.size(); ++i) r[i] = 1.0 + 0.01 * double((i * 7 + k) % 300);
		r[10] = 81.83;
		if (k == 5) r[11] = NAN;
		s += lrgc::test::odomLine(robot, t - 0.01);
		s += lrgc::test::flaserLine(r, {robot.x + 0.1, robot.y, robot.phi}, robot, t);
		if (k % 10 == 0)
		{
			s += lrgc::test::flaserLine(r, robot, robot, t + 0.02, "RLASER");
			s += lrgc::test::robotLaser1Line(-1.5, 3.0, 0.03, 30.0,
											 std::vector<double>(r.begin(), r.begin() + 101),
											 robot, robot, t + 0.03);
		}
	}
	return s;
}

void expectSameObservation(const mrpt::obs::CObservation& a, const mrpt::obs::CObservation& b)
{
	ASSERT_EQ(std::string(a.GetRuntimeClass()->className), b.GetRuntimeClass()->className);
	EXPECT_EQ(a.sensorLabel, b.sensorLabel);
	EXPECT_EQ(a.timestamp, b.timestamp);
	if (const auto* sa = dynamic_cast<const CObservation2DRangeScan*>(&a))
	{
		const auto& sb = dynamic_cast<const CObservation2DRangeScan&>(b);
		ASSERT_EQ(sa->getScanSize(), sb.getScanSize());
		for (size_t i = 0; i < sa->getScanSize(); ++i)
		{
			EXPECT_EQ(sa->getScanRangeValidity(i), sb.getScanRangeValidity(i));
			EXPECT_EQ(sa->getScanRange(i), sb.getScanRange(i));
		}
		EXPECT_EQ(sa->aperture, sb.aperture);
		EXPECT_EQ(sa->maxRange, sb.maxRange);
		EXPECT_EQ(sa->rightToLeft, sb.rightToLeft);
		EXPECT_EQ(sa->sensorPose, sb.sensorPose);
	}
	if (const auto* oa = dynamic_cast<const CObservationOdometry*>(&a))
	{
		const auto& ob = dynamic_cast<const CObservationOdometry&>(b);
		EXPECT_EQ(oa->odometry, ob.odometry);
		EXPECT_EQ(oa->hasVelocities, ob.hasVelocities);
	}
}

// Runs MRPT's rawlog-edit --info; returns its exit status and output.
std::pair<int, std::string> rawlogEditInfo(const std::string& path)
{
	const std::string cmd = "rawlog-edit -i '" + path + "' --info </dev/null 2>&1";
	FILE* p = ::popen(cmd.c_str(), "r");
	std::string out;
	if (!p) return {-1, out};
	char buf[4096];
	while (const size_t n = std::fread(buf, 1, sizeof(buf), p)) out.append(buf, n);
	const int status = ::pclose(p);
	return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

long objectCount(const std::string& info)
{
	std::smatch m;
	const std::regex re("Overall number of objects\\s*:\\s*(\\d+)");
	return std::regex_search(info, m, re) ? std::stol(m[1]) : -1;
}

bool haveRawlogEdit()
{
	return std::system("command -v rawlog-edit >/dev/null 2>&1") == 0;
}
}  // namespace

TEST(RawlogConversion, ConvertsACarmenLogLosslessly)
{
	const std::string dir = lrgc::test::makeTempDir("convert_carmen");
	const std::string in = dir + "/gen.clf.gz";
	lrgc::test::writeGzFile(in, generatedCarmen());
	const std::string out = dir + "/gen.rawlog";
	const TConversionStats st = convertToRawlog(in, out);
	const auto direct = readWholeLog(in);
	const auto back = readWholeLog(out);
	ASSERT_FALSE(back.error) << *back.error;
	EXPECT_EQ(detectLogFormat(out), LogFormat::MrptRawlog);
	EXPECT_EQ(st.scans, 60u + 6u + 6u);
	EXPECT_EQ(st.odometry, 60u + 72u);
	EXPECT_EQ(st.observations, back.entries.size());
	EXPECT_EQ(st.warnings, 3u);  // the NaN; the backward jumps of FLASER and of ODOM
	EXPECT_EQ(st.warningText.size(), 3u);
	EXPECT_TRUE(contains(st.warningText[0], in + ": line "));
	ASSERT_EQ(back.entries.size(), direct.entries.size());
	for (size_t i = 0; i < back.entries.size(); ++i)
		expectSameObservation(*direct.entries[i].observation, *back.entries[i].observation);
	// The reader of the converted file sees the backward jump again, now at a byte.
	EXPECT_EQ(back.stats.scanTimeJumpsBack, 1u);
	EXPECT_EQ(lrgc::test::readFileBytes(out).substr(0, 2), "\x1f\x8b") << "gzip, as MRPT";
}

TEST(RawlogConversion, MrptRawlogEditReadsTheOutput)
{
	if (!haveRawlogEdit()) GTEST_SKIP() << "rawlog-edit (Debian mrpt-apps) not installed";
	const std::string dir = lrgc::test::makeTempDir("convert_rawlog_edit");
	const std::string in = dir + "/gen.clf";
	lrgc::test::writeFileBytes(in, generatedCarmen());
	const std::string out = dir + "/gen.rawlog";
	const TConversionStats st = convertToRawlog(in, out);
	const auto [status, info] = rawlogEditInfo(out);
	EXPECT_EQ(status, 0) << info;
	EXPECT_EQ(objectCount(info), long(st.observations)) << info;
	EXPECT_TRUE(std::regex_search(info, std::regex("Observations format\\s*:\\s*Yes"))) << info;
}

TEST(RawlogConversion, FlattensALayout1RawlogIntoAbsoluteOdometry)
{
	LRGC_SKIP_IF_MISSING(lrgc::test::senaRawlogPath());
	const std::string dir = lrgc::test::makeTempDir("convert_sena");
	const std::string out = dir + "/sena-obs.rawlog";
	const TConversionStats st = convertToRawlog(lrgc::test::senaRawlogPath(), out);
	EXPECT_EQ(st.scans, 225u);
	EXPECT_EQ(st.odometry, 224u);
	const auto back = readWholeLog(out);
	ASSERT_FALSE(back.error);
	ASSERT_EQ(back.entries.size(), 449u);
	// Odometry_k = odometry_{k-1} (+) increment_k: the last one is the sum of them all.
	const auto sena = readWholeLog(lrgc::test::senaRawlogPath());
	mrpt::poses::CPose2D sum;
	for (const auto& e : sena.entries)
		if (const auto m = e.actions->getActionByClass<mrpt::obs::CActionRobotMovement2D>())
			sum = sum + m->poseChange->getMeanVal();
	std::shared_ptr<CObservationOdometry> last;
	for (const auto& e : back.entries)
		if (auto o = std::dynamic_pointer_cast<CObservationOdometry>(e.observation)) last = o;
	ASSERT_TRUE(last);
	EXPECT_NEAR(last->odometry.x(), sum.x(), 1e-9);
	EXPECT_NEAR(last->odometry.phi(), sum.phi(), 1e-9);
}

TEST(RawlogConversion, LeavesNoOutputWhenTheInputIsBad)
{
	const std::string dir = lrgc::test::makeTempDir("convert_bad");
	const std::string out = dir + "/out.rawlog";
	EXPECT_THROW(convertToRawlog(dir + "/missing.clf", out), CLogReadError);
	EXPECT_FALSE(lrgc::test::fileExists(out));
	// A truncated gzip input: the error comes at its end; a previous output stays intact.
	lrgc::test::writeFileBytes(out, "previous");
	const std::string in = dir + "/gen.clf.gz";
	lrgc::test::writeGzFile(in, generatedCarmen());
	const std::string bytes = lrgc::test::readFileBytes(in);
	lrgc::test::writeFileBytes(in, bytes.substr(0, bytes.size() - 3));
	try
	{
		convertToRawlog(in, out);
		ADD_FAILURE() << "a truncated input was converted";
	}
	catch (const CLogReadError& e)
	{
		EXPECT_TRUE(contains(e.what(), in + ": byte ")) << e.what();
	}
	EXPECT_EQ(lrgc::test::readFileBytes(out), "previous");
	EXPECT_EQ(std::system(("ls -A '" + dir + "' | grep -q '^\\.tmp'").c_str()) == 0, false)
		<< "temporary file left behind";
}

TEST(RawlogConversion, ConvertsIntelAndRawlogEditAgrees)
{
	const std::string intel = lrgc::test::sharedDatasetPath("intel/intel.clf.gz");
	LRGC_SKIP_IF_MISSING(intel);
	const std::string dir = lrgc::test::makeTempDir("convert_intel");
	const std::string out = dir + "/intel.rawlog";
	const TConversionStats st = convertToRawlog(intel, out);
	EXPECT_EQ(st.scans, 13631u);
	EXPECT_EQ(st.odometry, 13631u + 26915u);
	EXPECT_EQ(st.observations, st.scans + st.odometry);
	// Read back: the same timestamps, in the same order, as reading the CARMEN log.
	const auto a = openLog(intel), b = openLog(out);
	size_t n = 0;
	while (const auto ea = a->next())
	{
		const auto eb = b->next();
		ASSERT_TRUE(eb) << n;
		ASSERT_EQ(ea->observation->timestamp, eb->observation->timestamp) << n;
		ASSERT_EQ(ea->observation->sensorLabel, eb->observation->sensorLabel) << n;
		++n;
	}
	EXPECT_FALSE(b->next());
	EXPECT_EQ(b->stats().scanTimeJumpsBack, 631u);
	if (!haveRawlogEdit()) return;
	const auto [status, info] = rawlogEditInfo(out);
	EXPECT_EQ(status, 0) << info;
	EXPECT_EQ(objectCount(info), long(st.observations)) << info;
}
