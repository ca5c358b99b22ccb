/* pf-localization.ini and observations2map.ini texts: the particle box around the start pose
 * in the map's frame, absolute paths, and what a CARMEN run without a rawlog says. */
#include "MrptClientFiles.h"

#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>

using namespace lrgc::apps;

TEST(MrptClientFiles, PfLocalizationBoxIsAroundTheStartPose)
{
	const mrpt::config::CConfigFileMemory ini(
		pfLocalizationIni("/data/out", "/logs/a b.rawlog", {2.0, -1.0, M_PI / 2}, 0.05));
	const std::string s = "LocalizationExperiment";
	EXPECT_EQ(ini.read_string(s, "map_file", ""), "/data/out/map.gridmap.gz");
	EXPECT_EQ(ini.read_string(s, "rawlog_file", ""), "/logs/a b.rawlog");
	EXPECT_DOUBLE_EQ(ini.read_double(s, "init_PDF_min_x", 0), 1.5);
	EXPECT_DOUBLE_EQ(ini.read_double(s, "init_PDF_max_x", 0), 2.5);
	EXPECT_DOUBLE_EQ(ini.read_double(s, "init_PDF_min_y", 0), -1.5);
	EXPECT_DOUBLE_EQ(ini.read_double(s, "init_PDF_max_y", 0), -0.5);
	EXPECT_DOUBLE_EQ(ini.read_double(s, "init_PDF_min_yaw_deg", 0), 80);
	EXPECT_DOUBLE_EQ(ini.read_double(s, "init_PDF_max_yaw_deg", 0), 100);
	EXPECT_EQ(ini.read_int(s, "3DSceneFrequency", 0), -1);
	EXPECT_FALSE(ini.read_bool(s, "SHOW_PROGRESS_3D_REAL_TIME", true));
	// A prefix of pf-localization's own folder (which it empties): never the output folder.
	EXPECT_EQ(ini.read_string(s, "logOutput_dir", ""), "/data/out/pf-localization-log");
	EXPECT_DOUBLE_EQ(
		ini.read_double("MetricMap_occupancyGrid_00_creationOpts", "resolution", 0), 0.05);
}

TEST(MrptClientFiles, WithoutARawlogTheFileSaysHowToMakeOne)
{
	const std::string text = pfLocalizationIni("/data/out", "", {}, 0.05);
	EXPECT_NE(text.find("lrgc-slam --input LOG --save-rawlog LOG.rawlog"), std::string::npos)
		<< text;
	const mrpt::config::CConfigFileMemory ini(text);
	EXPECT_EQ(ini.read_string("LocalizationExperiment", "rawlog_file", "x"), "");
}

TEST(MrptClientFiles, Observations2mapHasOurGridSettings)
{
	const mrpt::config::CConfigFileMemory ini(observations2mapIni(0.04, 25));
	EXPECT_EQ(ini.read_int("MappingApplication", "occupancyGrid_count", 0), 1);
	EXPECT_DOUBLE_EQ(
		ini.read_double("MappingApplication_occupancyGrid_00_creationOpts", "resolution", 0),
		0.04);
	EXPECT_DOUBLE_EQ(ini.read_double("MappingApplication_occupancyGrid_00_insertOpts",
									 "maxDistanceInsertion", 0),
					 25);
}
