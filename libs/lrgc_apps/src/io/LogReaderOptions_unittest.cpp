#include <gtest/gtest.h>
#include <lrgc_apps/io/LogReaderOptions.h>
#include <mrpt/config/CConfigFileMemory.h>

using lrgc::apps::TLogReaderOptions;

TEST(LogReaderOptions, RoundTripsThroughIniText)
{
	TLogReaderOptions a;
	a.carmen_180_beams_fov = 170 * M_PI / 180;
	a.carmen_max_range_m = 30;
	mrpt::config::CConfigFileMemory ini;
	a.saveToConfigFile(ini, "LogReader");
	mrpt::config::CConfigFileMemory reread(ini.getContent());
	TLogReaderOptions b;
	b.loadFromConfigFile(reread, "LogReader");
	EXPECT_NEAR(b.carmen_180_beams_fov, a.carmen_180_beams_fov, 1e-9);
	EXPECT_DOUBLE_EQ(b.carmen_max_range_m, 30);
	EXPECT_NE(ini.getContent().find("carmen_180_beams_fov_deg"), std::string::npos);
	EXPECT_NE(ini.getContent().find("170"), std::string::npos) << "saved in degrees";
}

TEST(LogReaderOptions, DefaultsAreTheDocumentedOnes)
{
	const TLogReaderOptions o;
	EXPECT_DOUBLE_EQ(o.carmen_180_beams_fov, 179 * M_PI / 180);
	EXPECT_DOUBLE_EQ(o.carmen_max_range_m, 50.0);
	mrpt::config::CConfigFileMemory empty;
	TLogReaderOptions p;
	p.loadFromConfigFile(empty, "LogReader");
	EXPECT_DOUBLE_EQ(p.carmen_180_beams_fov, 179 * M_PI / 180);
}

TEST(LogReaderOptions, RejectsUnknownKeysAndBadValues)
{
	TLogReaderOptions o;
	mrpt::config::CConfigFileMemory misspelt("[LogReader]\ncarmen_max_rang_m = 40\n");
	EXPECT_ANY_THROW(o.loadFromConfigFile(misspelt, "LogReader"));
	mrpt::config::CConfigFileMemory zeroFov("[LogReader]\ncarmen_180_beams_fov_deg = 0\n");
	EXPECT_ANY_THROW(o.loadFromConfigFile(zeroFov, "LogReader"));
	mrpt::config::CConfigFileMemory negative("[LogReader]\ncarmen_max_range_m = -1\n");
	EXPECT_ANY_THROW(o.loadFromConfigFile(negative, "LogReader"));
	try
	{
		o.loadFromConfigFile(misspelt, "LogReader");
	}
	catch (const std::exception& e)
	{
		EXPECT_NE(std::string(e.what()).find("carmen_max_range_m"), std::string::npos)
			<< "suggests the intended key";
	}
}
