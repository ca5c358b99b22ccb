/* CLiveSlam in-process with scripted fake sensors: the whole live pipeline (sensor thread,
 * queues, capture writer, mapper, saves) in a fraction of a second, no hardware, no network. */
#include <gtest/gtest.h>
#include "SlamApp.h"
#include "live/LiveSlam.h"
#include "live/LiveSlamTestAccess.h"
#include "live/LiveSlam_unittest.h"

#include <atomic>
#include <cstdio>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "FakeSensors.h"
#include "app_runner.h"
#include "lms1xx_emulator.h"  // waitUntil
#include "test_data.h"

using namespace lrgc::apps;
using lrgc_test_fakes::laserScript;
namespace fs = std::filesystem;
using lrgc::apps::live_test::jsonInt;
using lrgc::apps::live_test::lines;

namespace
{
/** Runs a live session on the fakes until every scripted scan was handed over. */
class LiveSlamTest : public ::testing::Test
{
protected:
	void SetUp() override
	{
		lrgc_test_fakes::registerFakeSensors();
		laserScript().reset();
		m_dir = lrgc::test::makeTempDir(
			std::string("live_") +
			::testing::UnitTest::GetInstance()->current_test_info()->name());
		m_sensors = m_dir + "/sensors.ini";
		lrgc::test::writeTextFile(
			m_sensors,
			"[global]\nrawlog_prefix = ./x\n\n[LASER]\ndriver = CFakeLiveLaser\n"
			"process_rate = 200\nsensorLabel = FAKE\n");
		m_setup.sensorsIni = m_sensors;
		m_setup.outDir = m_dir + "/out";
		m_setup.config.live.status_interval_s = 0.05;
		m_setup.config.live.save_interval_s = 0.05;
		m_setup.config.live.max_backlog_scans = 0;
	}
	int run()
	{
		char* buf = nullptr;
		size_t size = 0;
		std::FILE* err = open_memstream(&buf, &size);
		CLiveSlam app(m_setup, err);
		TLiveSlamTestAccess::setPeriodicSaveHook(app, m_saveHook);
		const int rc = app.run([] { return laserScript().allHandedOver.load(); });
		std::fclose(err);
		m_console.assign(buf, size);
		std::free(buf);
		return rc;
	}
	std::string out(const std::string& name) const { return m_setup.outDir + "/" + name; }

	std::string m_dir, m_sensors, m_console;
	TLiveSlamSetup m_setup;
	TPeriodicSaveHook m_saveHook;
};
}  // namespace

TEST_F(LiveSlamTest, MapsEveryScanAndTheCaptureReplaysToTheSameTrajectory)
{
	lrgc_test_fakes::makeRoomRun(150, laserScript());
	ASSERT_EQ(run(), kExitOk) << m_console;
	const std::string live = lrgc::test::readTextFile(out("live.json"));
	EXPECT_EQ(jsonInt(live, "objects"), 300) << live;  // capture: 150 scans + 150 odometry
	EXPECT_EQ(jsonInt(live, "scans_mapped"), 150);
	EXPECT_EQ(jsonInt(live, "odometry"), 150);
	EXPECT_EQ(jsonInt(live, "skipped_to_keep_up"), 0);
	EXPECT_NE(m_console.find("live: maps saved ("), std::string::npos) << "periodic save";
	EXPECT_NE(m_console.find("live: received 150 scans, mapped 150"), std::string::npos)
		<< m_console;

	const std::string replay = m_dir + "/replay";
	std::FILE* devnull = std::fopen("/dev/null", "w");
	const int rc =
		CSlamApp(devnull).run({"--input", out("capture.rawlog"), "--out", replay, "--quiet"});
	std::fclose(devnull);
	ASSERT_EQ(rc, kExitOk);
	const auto a = lines(out("trajectory.tum")), b = lines(replay + "/trajectory.tum");
	EXPECT_EQ(a.size(), 150u);
	EXPECT_EQ(a, b) << "live and replayed trajectories differ";
	EXPECT_EQ(lrgc::test::readTextFile(out("graph.graph")),
			  lrgc::test::readTextFile(replay + "/graph.graph"));
}

// Saves run on the saver thread, never on the mapping thread: a save made slow on purpose
// waits, inside the save, until 20 more scans are mapped. Were the save on the mapping thread,
// no scan could be mapped until it returned, and the wait would time out (no timing is
// asserted: the bound only ends a failing test).
TEST_F(LiveSlamTest, ASlowSaveNeverHoldsUpMapping)
{
	lrgc_test_fakes::makeRoomRun(200, laserScript());
	const size_t n = laserScript().scans.size();
	std::atomic<int> saves{0};
	std::atomic<size_t> mappedAtSaveStart{0};
	std::atomic<bool> mappedDuringSave{false};
	m_saveHook = [&](const std::function<size_t()>& scansMapped)
	{
		if (saves++ > 0) return;
		mappedAtSaveStart = scansMapped();
		const size_t target = std::min(mappedAtSaveStart + 20, n);
		mappedDuringSave = lrgc::test::waitUntil([&] { return scansMapped() >= target; }, 60);
	};
	ASSERT_EQ(run(), kExitOk) << m_console;
	ASSERT_GE(saves.load(), 1);
	EXPECT_LT(mappedAtSaveStart.load(), n - 20) << "the first save came too late to tell";
	EXPECT_TRUE(mappedDuringSave) << "mapping stopped while a save ran";
	const std::string live = lrgc::test::readTextFile(out("live.json"));
	EXPECT_EQ(jsonInt(live, "scans_mapped"), static_cast<long>(n));
	EXPECT_GE(jsonInt(live, "saves"), 2) << "the slow periodic save and the final one";
	EXPECT_NE(m_console.find("live: maps saved ("), std::string::npos) << m_console;
	EXPECT_EQ(lines(out("trajectory.tum")).size(), n);
}

TEST_F(LiveSlamTest, FallingBehindSkipsScansButNeverOdometryOrTheCapture)
{
	lrgc_test_fakes::makeRoomRun(1000, laserScript());  // the whole path
	const long n = static_cast<long>(laserScript().scans.size());
	ASSERT_GT(n, 200);
	// Bursts of 100 scans (+100 odometry: CGenericSensor keeps at most max_queue_len = 200
	// objects between two getObservations()): the mapper is far behind at once.
	laserScript().scansPerCall = 100;
	m_setup.config.live.max_backlog_scans = 5;
	ASSERT_EQ(run(), kExitOk) << m_console;
	const std::string live = lrgc::test::readTextFile(out("live.json"));
	const long mapped = jsonInt(live, "scans_mapped"),
			   skipped = jsonInt(live, "skipped_to_keep_up");
	EXPECT_GT(skipped, 0);
	EXPECT_GT(mapped, 0);
	EXPECT_EQ(mapped + skipped, n);
	EXPECT_EQ(jsonInt(live, "odometry"), n) << "odometry is never skipped";
	EXPECT_EQ(jsonInt(live, "objects"), 2 * n) << "the capture keeps everything";
	EXPECT_NE(m_console.find("live: mapping is behind"), std::string::npos) << m_console;
	EXPECT_EQ(lines(out("trajectory.tum")).size(), static_cast<size_t>(mapped));
}

// No sensor delivers (doc/live.md): each is reported as not started, and the run, once
// stopped, ends with exit status 1 saying so.
TEST_F(LiveSlamTest, NoSensorDeliveringIsReportedAndExitsNonZero)
{
	laserScript().silentAfter = 0;  // initialize() succeeds, then only 0-ray scans
	m_setup.config.live.sensor_timeout_s = 0.2;
	m_setup.config.live.retry_initial_s = 0.01;
	m_setup.config.live.retry_max_s = 0.02;
	char* buf = nullptr;
	size_t size = 0;
	std::FILE* err = open_memstream(&buf, &size);
	const auto t0 = std::chrono::steady_clock::now();
	const int rc =
		CLiveSlam(m_setup, err)
			.run([&]
				 { return std::chrono::steady_clock::now() - t0 > std::chrono::seconds(1); });
	std::fclose(err);
	m_console.assign(buf, size);
	std::free(buf);
	EXPECT_EQ(rc, kExitInputError) << m_console;
	EXPECT_NE(m_console.find("[LASER] CFakeLiveLaser cannot start: no valid data within 0.2 s"),
			  std::string::npos)
		<< m_console;
	EXPECT_EQ(m_console.find("LASER ok"), std::string::npos) << m_console;
	EXPECT_NE(m_console.find("lrgc-slam: no sensor delivered data ([LASER] CFakeLiveLaser "
							 "cannot start: no valid data within 0.2 s"),
			  std::string::npos)
		<< m_console;
}

TEST_F(LiveSlamTest, AnExistingCaptureIsNeverOverwritten)
{
	fs::create_directories(m_setup.outDir);
	lrgc::test::writeTextFile(out("capture.rawlog"), "precious");
	EXPECT_THROW(run(), CUsageError);
	EXPECT_EQ(lrgc::test::readTextFile(out("capture.rawlog")), "precious");
}

TEST_F(LiveSlamTest, AnUnknownDriverIsAUsageErrorBeforeAnythingIsWritten)
{
	lrgc::test::writeTextFile(m_sensors, "[LASER]\ndriver = CNoSuchLaser\nprocess_rate = 10\n");
	try
	{
		run();
		ADD_FAILURE() << "no error";
	}
	catch (const CUsageError& e)
	{
		EXPECT_NE(std::string(e.what()).find("[LASER]: driver 'CNoSuchLaser'"),
				  std::string::npos)
			<< e.what();
	}
	EXPECT_FALSE(fs::exists(out("capture.rawlog")));
}
