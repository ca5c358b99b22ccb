/* CLiveSlam on a saved map, in-process with the scripted fake laser (FakeSensors.h): a first
 * live run maps the synthetic room, a second one drives the same path again with --localize
 * or --initial-map on that map. With results applied on the offline schedule
 * (loop_results_when_ready = false) and no scan skipped, the live run must give exactly what
 * the offline app gives on its capture: the same localiser or map builder, fed the same
 * observations in the same order. */
#include <gtest/gtest.h>
#include "SlamApp.h"
#include "lrgc_apps/SavedMap.h"
#include "live/LiveSlam.h"
#include "live/LiveSlam_unittest.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>

#include "FakeSensors.h"
#include "app_runner.h"
#include "test_data.h"

using namespace lrgc::apps;
using lrgc_test_fakes::laserScript;
namespace fs = std::filesystem;
using lrgc::apps::live_test::jsonInt;
using lrgc::apps::live_test::lines;

namespace
{
class LiveSlamSavedMapTest : public ::testing::Test
{
protected:
	void SetUp() override
	{
		lrgc_test_fakes::registerFakeSensors();
		m_dir = lrgc::test::makeTempDir(
			std::string("live_saved_") +
			::testing::UnitTest::GetInstance()->current_test_info()->name());
		m_setup.sensorsIni = m_dir + "/sensors.ini";
		lrgc::test::writeTextFile(
			m_setup.sensorsIni,
			"[global]\nrawlog_prefix = ./x\n\n[LASER]\ndriver = CFakeLiveLaser\n"
			"process_rate = 200\nsensorLabel = FAKE\n");
		m_setup.config.live.status_interval_s = 0.05;
		m_setup.config.live.save_interval_s = 0.05;
		m_setup.config.live.max_backlog_scans = 0;
		m_setup.config.live.loop_results_when_ready = false;
		// The room's map, mapped live.
		ASSERT_EQ(run(m_dir + "/map"), kExitOk) << m_console;
	}
	/** A live run of the room's path into `outDir`. */
	int run(const std::string& outDir)
	{
		laserScript().reset();
		lrgc_test_fakes::makeRoomRun(150, laserScript());
		m_setup.outDir = outDir;
		char* buf = nullptr;
		size_t size = 0;
		std::FILE* err = open_memstream(&buf, &size);
		const int rc =
			CLiveSlam(m_setup, err).run([] { return laserScript().allHandedOver.load(); });
		std::fclose(err);
		m_console.assign(buf, size);
		std::free(buf);
		return rc;
	}
	/** The offline app on the capture of `outDir` with `args`; its output folder. */
	std::string offline(const std::string& outDir, std::vector<std::string> args)
	{
		const std::string replay = outDir + "-offline";
		args.insert(args.end(),
					{"--input", outDir + "/capture.rawlog", "--out", replay, "--quiet"});
		std::FILE* devnull = std::fopen("/dev/null", "w");
		EXPECT_EQ(CSlamApp(devnull).run(args), kExitOk);
		std::fclose(devnull);
		return replay;
	}

	std::string m_dir, m_console;
	TLiveSlamSetup m_setup;
};
}  // namespace

// --localize: every scan localised, saved periodically and at the end, and the poses are those
// of the offline --localize run on the capture, exactly.
TEST_F(LiveSlamSavedMapTest, LocalisesOnTheMapAsOfflineDoes)
{
	m_setup.localizeMap = loadSavedMap(m_dir + "/map", "--localize");
	const std::string out = m_dir + "/loc";
	ASSERT_EQ(run(out), kExitOk) << m_console;
	const std::string stats = lrgc::test::readTextFile(out + "/stats.json");
	EXPECT_NE(stats.find("\"mode\": \"localize\""), std::string::npos) << stats;
	EXPECT_EQ(jsonInt(stats, "scans"), 150) << stats;
	EXPECT_EQ(jsonInt(stats, "localized_scans"), 150) << stats;
	EXPECT_NE(m_console.find("live: poses saved ("), std::string::npos) << "periodic save";
	EXPECT_NE(m_console.find("started at"), std::string::npos) << m_console;
	EXPECT_FALSE(fs::exists(out + "/.trajectory.tum.stream"));
	EXPECT_FALSE(fs::exists(out + "/map.simplemap.gz")) << "localisation writes no map";
	EXPECT_EQ(lines(out + "/timing.csv").size(), 151u);
	const auto live = lines(out + "/trajectory.tum");
	EXPECT_EQ(live.size(), 150u);
	const std::string replay = offline(out, {"--localize", m_dir + "/map"});
	EXPECT_EQ(live, lines(replay + "/trajectory.tum")) << "live and offline poses differ";
}

// --initial-map: the start is found, the map continued (the same path: keyframes reused, few
// new ones), and the result is the offline --initial-map run's on the capture, exactly.
TEST_F(LiveSlamSavedMapTest, ContinuesTheMapAsOfflineDoes)
{
	const long before =
		jsonInt(lrgc::test::readTextFile(m_dir + "/map/stats.json"), "keyframes");
	m_setup.initialMap = loadSavedMap(m_dir + "/map", "--initial-map");
	const std::string out = m_dir + "/cont";
	ASSERT_EQ(run(out), kExitOk) << m_console;
	EXPECT_NE(m_console.find("live: the log starts at"), std::string::npos) << m_console;
	const std::string stats = lrgc::test::readTextFile(out + "/stats.json");
	EXPECT_NE(stats.find("\"joined\": true"), std::string::npos) << stats;
	EXPECT_NE(stats.find("\"frame\": \"map\""), std::string::npos) << stats;
	EXPECT_EQ(jsonInt(stats, "scans"), 150) << stats;
	const long keyframes = jsonInt(stats, "keyframes");
	EXPECT_GE(keyframes, before);
	EXPECT_LE(keyframes, before + before / 4) << "the same path again: keyframes reused";
	const std::string replay = offline(out, {"--initial-map", m_dir + "/map"});
	EXPECT_EQ(lines(out + "/trajectory.tum"), lines(replay + "/trajectory.tum"));
	EXPECT_EQ(lrgc::test::readTextFile(out + "/graph.graph"),
			  lrgc::test::readTextFile(replay + "/graph.graph"));
}

// --initial-map where no correlation can pass (max_std_xy_m 0.1 mm, far below any estimate):
// the session is mapped as a piece of its own from its first scan and never joined; as offline
// it is kept and saved in its own frame, exit 0, and the live map is the offline one.
TEST_F(LiveSlamSavedMapTest, KeepsASessionNeverJoined)
{
	const long before =
		jsonInt(lrgc::test::readTextFile(m_dir + "/map/stats.json"), "keyframes");
	m_setup.config.lrgc.correlator.max_std_xy_m = 1e-4;
	m_setup.initialMap = loadSavedMap(m_dir + "/map", "--initial-map");
	const std::string out = m_dir + "/kept";
	ASSERT_EQ(run(out), kExitOk) << m_console;
	EXPECT_NE(m_console.find("mapping as a piece not yet joined ("), std::string::npos)
		<< m_console;
	EXPECT_NE(m_console.find("live: the log was not joined to the map"), std::string::npos)
		<< m_console;
	EXPECT_EQ(m_console.find("no start found"), std::string::npos) << m_console;
	const std::string stats = lrgc::test::readTextFile(out + "/stats.json");
	EXPECT_NE(stats.find("\"joined\": false"), std::string::npos) << stats;
	EXPECT_NE(stats.find("\"frame\": \"the log's own frame (its first scan at"),
			  std::string::npos)
		<< stats;
	EXPECT_GT(jsonInt(stats, "start_attempts"), 0) << stats;
	EXPECT_EQ(jsonInt(stats, "scans"), 150) << stats;
	EXPECT_GT(jsonInt(stats, "keyframes"), before) << "the piece's keyframes beside the map";
	EXPECT_EQ(lines(out + "/trajectory.tum").size(), 150u);
	const std::string ini = m_dir + "/max_std.ini";
	lrgc::test::writeTextFile(ini, "[PatchCorrelator]\nmax_std_xy_m = 0.0001\n");
	const std::string replay = offline(out, {"--initial-map", m_dir + "/map", "--config", ini});
	EXPECT_EQ(lines(out + "/trajectory.tum"), lines(replay + "/trajectory.tum"));
	EXPECT_EQ(lrgc::test::readTextFile(out + "/graph.graph"),
			  lrgc::test::readTextFile(replay + "/graph.graph"));
}
