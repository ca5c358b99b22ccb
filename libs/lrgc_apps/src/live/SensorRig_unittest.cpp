#include <gtest/gtest.h>
#include "CommandLine.h"
#include "live/SensorRig.h"
#include <mrpt/core/exceptions.h>

#include "FakeSensors.h"
#include "app_runner.h"
#include "test_data.h"

using namespace lrgc::apps;

namespace
{
std::string writeIni(const std::string& name, const std::string& text)
{
	const std::string path = lrgc::test::makeTempDir("sensor_rig_" + name) + "/s.ini";
	lrgc::test::writeTextFile(path, text);
	return path;
}

std::string usageError(const std::string& iniText)
{
	try
	{
		loadSensorRig(writeIni("err", iniText));
	}
	catch (const CUsageError& e)
	{
		return e.what();
	}
	return "(no error)";
}
}  // namespace

TEST(SensorRig, ReadsAGrabberIniLikeRawlogGrabber)
{
	lrgc_test_fakes::registerFakeSensors();
	const auto rig = loadSensorRig(writeIni(
		"ok",
		"[global]\nrawlog_prefix = ./d\ntime_between_launches = 300\nuse_sensoryframes = 0\n"
		"rawlog_prefx = typo\n\n"
		"[LASER1]\ndriver = CFakeLiveLaser\nprocess_rate = 30\nsensorLabel = FRONT\n\n"
		"[LASER2]\ndriver = CLMS100Eth\nprocess_rate = 25\nip_address = 127.0.0.1\n"));
	ASSERT_EQ(rig.sensors.size(), 2u);
	EXPECT_EQ(rig.sensors[0].section, "LASER1");
	EXPECT_EQ(rig.sensors[0].driver, "CFakeLiveLaser");
	EXPECT_EQ(rig.sensors[0].label, "FRONT");
	EXPECT_DOUBLE_EQ(rig.sensors[0].processRate, 30);
	EXPECT_EQ(rig.sensors[1].driver, "CLMS100Eth");
	EXPECT_EQ(rig.sensors[1].label, "SICK");  // CLMS100Eth's default label
	ASSERT_EQ(rig.notes.size(), 2u);
	EXPECT_NE(rig.notes[0].find("[global] is rawlog-grabber's section"), std::string::npos);
	EXPECT_NE(rig.notes[1].find("[global] rawlog_prefx: not a rawlog-grabber key"),
			  std::string::npos);
}

TEST(SensorRig, MrptsOwnGrabberExamplesAreAccepted)
{
	for (const char* name : {"SICK_LMS_serial.ini", "hokuyo_UTM.ini"})
	{
		const std::string path =
			std::string("/usr/share/mrpt/config_files/rawlog-grabber/") + name;
		if (!lrgc::test::fileExists(path)) GTEST_SKIP() << "not installed here: " << path;
		const auto rig = loadSensorRig(path);
		ASSERT_EQ(rig.sensors.size(), 1u) << path;
		EXPECT_GT(rig.sensors[0].processRate, 0) << path;
	}
}

TEST(SensorRig, ShippedLiveExampleIsValid)
{
	const auto rig =
		loadSensorRig(std::string(LRGC_SOURCE_DIR) + "/share/lrgc/live-sick-lms1xx.ini");
	ASSERT_EQ(rig.sensors.size(), 1u);
	EXPECT_EQ(rig.sensors[0].driver, "CLMS100Eth");
	EXPECT_GT(rig.sensors[0].processRate, 0);
}

TEST(SensorRig, ProblemsAreUsageErrorsNamingFileSectionAndKey)
{
	lrgc_test_fakes::registerFakeSensors();
	EXPECT_NE(usageError("[LASER]\nprocess_rate = 10\n").find("[LASER]: no `driver` key"),
			  std::string::npos);
	EXPECT_NE(usageError("[LASER]\ndriver = CSickLaserSerail\nprocess_rate = 10\n")
				  .find("[LASER]: driver 'CSickLaserSerail' is not a sensor class"),
			  std::string::npos);
	EXPECT_NE(usageError("[LASER]\ndriver = CFakeLiveLaser\nprocess_rate = 0\n")
				  .find("[LASER]: process_rate must be set"),
			  std::string::npos);
	EXPECT_NE(usageError("[global]\nrawlog_prefix = x\n").find("no sensor section"),
			  std::string::npos);
	EXPECT_THROW(loadSensorRig("/nonexistent/sensors.ini"), CUsageError);
}
