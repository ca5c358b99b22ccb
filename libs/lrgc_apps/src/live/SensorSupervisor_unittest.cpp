#include <gtest/gtest.h>
#include <lrgc_apps/live/SensorSupervisor.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <mutex>

#include "FakeSensors.h"
#include "lms1xx_emulator.h"  // waitUntil

using namespace lrgc::apps;
using lrgc_test_fakes::laserScript;

namespace
{
class SensorSupervisorTest : public ::testing::Test
{
protected:
	void SetUp() override
	{
		lrgc_test_fakes::registerFakeSensors();
		laserScript().reset();
		lrgc_test_fakes::makeRoomRun(20, laserScript());
		m_params.sensor_timeout_s = 0.2;
		m_params.retry_initial_s = 0.01;
		m_params.retry_max_s = 0.03;
	}

	std::unique_ptr<CSensorSupervisor> make(const std::string& driver,
											const std::string& section = "LASER")
	{
		m_ini.write(section, "driver", driver);
		m_ini.write(section, "process_rate", 500);
		TSensorSection s{section, driver, section, 500};
		return std::make_unique<CSensorSupervisor>(
			m_ini, s, m_params,
			[this](const mrpt::serialization::CSerializable::Ptr& o)
			{
				std::lock_guard<std::mutex> lock(m_mutex);
				m_received.push_back(o);
				return true;
			},
			[this](const std::string& line, bool)
			{
				std::lock_guard<std::mutex> lock(m_mutex);
				m_lines.push_back(line);
			});
	}
	size_t scansReceived()
	{
		std::lock_guard<std::mutex> lock(m_mutex);
		size_t n = 0;
		for (const auto& o : m_received)
			n += std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(o) != nullptr;
		return n;
	}
	size_t linesWith(const std::string& text)
	{
		std::lock_guard<std::mutex> lock(m_mutex);
		size_t n = 0;
		for (const auto& l : m_lines) n += l.find(text) != std::string::npos;
		return n;
	}
	/** The scans received are the script's, in order, each once. */
	void expectAllScansInOrder()
	{
		std::lock_guard<std::mutex> lock(m_mutex);
		std::vector<mrpt::serialization::CSerializable::Ptr> scans;
		for (const auto& o : m_received)
			if (std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(o))
				scans.push_back(o);
		ASSERT_EQ(scans.size(), laserScript().scans.size());
		for (size_t i = 0; i < scans.size(); ++i)
			EXPECT_EQ(scans[i], laserScript().scans[i]) << i;
	}

	mrpt::config::CConfigFileMemory m_ini;
	TLiveMappingParams m_params;
	std::mutex m_mutex;
	std::vector<mrpt::serialization::CSerializable::Ptr> m_received;
	std::vector<std::string> m_lines;
};
}  // namespace

TEST_F(SensorSupervisorTest, StartFailuresAreRetriedWithDoublingBackOff)
{
	laserScript().failStarts = 3;
	auto sup = make("CFakeLiveLaser");
	sup->start();
	ASSERT_TRUE(lrgc::test::waitUntil([&] { return scansReceived() == 20; }, 60));
	sup->requestStop();
	sup->join();
	EXPECT_EQ(
		linesWith("[LASER] CFakeLiveLaser cannot start: fake laser: no device on the port"),
		3u);
	EXPECT_EQ(linesWith("retrying in 0.01 s"), 1u);
	EXPECT_EQ(linesWith("retrying in 0.02 s"), 1u);
	EXPECT_EQ(linesWith("retrying in 0.03 s"), 1u);  // capped at retry_max_s
	const TSensorCounters c = sup->counters();
	EXPECT_EQ(c.starts, 1u);
	EXPECT_EQ(c.failures, 3u);
	EXPECT_EQ(c.scans, 20u);
	EXPECT_EQ(c.observations, 40u);  // with the odometry
	EXPECT_EQ(c.state, "stopped");
	expectAllScansInOrder();
}

TEST_F(SensorSupervisorTest, SilentSensorIsRestartedAndRecoveryReported)
{
	laserScript().silentAfter = 5;  // each instance: 5 scans, then 0-ray scans only
	auto sup = make("CFakeLiveLaser");
	sup->start();
	ASSERT_TRUE(lrgc::test::waitUntil([&] { return scansReceived() == 20; }, 60));
	sup->requestStop();
	sup->join();
	const TSensorCounters c = sup->counters();
	EXPECT_GE(c.starts, 4u);
	EXPECT_GE(c.failures, 3u);
	EXPECT_GT(c.rejected, 0u) << "0-ray scans are counted, not handed over";
	EXPECT_GE(linesWith("sent no valid data for 0.2 s: driver working"), 3u);
	EXPECT_GE(linesWith("observation(s) without data"), 3u);
	EXPECT_GE(linesWith("[LASER] CFakeLiveLaser data again after"), 3u);
	expectAllScansInOrder();
}

TEST_F(SensorSupervisorTest, DriverExceptionRestartsTheDriver)
{
	laserScript().throwAfter = 7;
	auto sup = make("CFakeLiveLaser");
	sup->start();
	ASSERT_TRUE(lrgc::test::waitUntil([&] { return scansReceived() == 20; }, 60));
	sup->requestStop();
	sup->join();
	EXPECT_EQ(linesWith("[LASER] CFakeLiveLaser failed: fake laser: checksum error"), 1u);
	EXPECT_EQ(sup->counters().starts, 2u);
	expectAllScansInOrder();
}

TEST_F(SensorSupervisorTest, ADeadSensorDoesNotHoldUpAnother)
{
	auto dead = make("CFakeDeadSensor", "BROKEN");
	auto laser = make("CFakeLiveLaser");
	dead->start();
	laser->start();
	ASSERT_TRUE(lrgc::test::waitUntil([&] { return scansReceived() == 20; }, 60));
	EXPECT_GE(dead->counters().failures, 1u);
	EXPECT_EQ(dead->counters().starts, 0u);
	EXPECT_GE(linesWith("[BROKEN] CFakeDeadSensor cannot start: fake dead sensor: cable cut"),
			  1u);
	dead->requestStop();
	laser->requestStop();
	dead->join();
	laser->join();
	expectAllScansInOrder();
}

TEST_F(SensorSupervisorTest, StopEndsABackOffWait)
{
	m_params.retry_initial_s = m_params.retry_max_s = 3600;
	auto dead = make("CFakeDeadSensor", "BROKEN");
	dead->start();
	ASSERT_TRUE(lrgc::test::waitUntil([&] { return dead->counters().failures == 1; }, 60));
	dead->requestStop();
	dead->join();  // would wait an hour if the back-off ignored the stop
	EXPECT_EQ(dead->counters().state, "stopped");
}

TEST_F(SensorSupervisorTest, ADriverStuckInACallIsShownAsBlocked)
{
	auto sup = make("CFakeLiveLaser");
	sup->start();
	ASSERT_TRUE(lrgc::test::waitUntil([&] { return scansReceived() >= 3; }, 60));
	laserScript().block = true;
	ASSERT_TRUE(lrgc::test::waitUntil(
		[&] { return sup->counters().state.rfind("blocked ", 0) == 0; }, 60))
		<< sup->counters().state;
	laserScript().block = false;
	ASSERT_TRUE(lrgc::test::waitUntil([&] { return scansReceived() == 20; }, 60));
	sup->requestStop();
	sup->join();
	expectAllScansInOrder();
}
