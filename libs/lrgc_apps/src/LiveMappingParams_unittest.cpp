#include <gtest/gtest.h>
#include <lrgc_apps/LiveMappingParams.h>
#include <mrpt/config/CConfigFileMemory.h>

using lrgc::apps::TLiveMappingParams;

TEST(LiveMappingParams, TextRoundTrip)
{
	TLiveMappingParams a;
	a.save_interval_s = 12.5;
	a.status_interval_s = 0.5;
	a.max_backlog_scans = 0;
	a.sensor_timeout_s = 1.5;
	a.retry_initial_s = 0.25;
	a.retry_max_s = 8;
	mrpt::config::CConfigFileMemory ini;
	a.saveToConfigFile(ini, "LiveMapping");
	const mrpt::config::CConfigFileMemory reread(ini.getContent());
	TLiveMappingParams b;
	b.loadFromConfigFile(reread, "LiveMapping");
	EXPECT_DOUBLE_EQ(b.save_interval_s, 12.5);
	EXPECT_DOUBLE_EQ(b.status_interval_s, 0.5);
	EXPECT_EQ(b.max_backlog_scans, 0u);
	EXPECT_DOUBLE_EQ(b.sensor_timeout_s, 1.5);
	EXPECT_DOUBLE_EQ(b.retry_initial_s, 0.25);
	EXPECT_DOUBLE_EQ(b.retry_max_s, 8);
}

TEST(LiveMappingParams, UnknownKeysAndBadValuesAreErrors)
{
	TLiveMappingParams p;
	EXPECT_ANY_THROW(p.loadFromConfigFile(
		mrpt::config::CConfigFileMemory("[LiveMapping]\nsave_interval = 5\n"), "LiveMapping"));
	EXPECT_ANY_THROW(p.loadFromConfigFile(
		mrpt::config::CConfigFileMemory("[LiveMapping]\nmax_backlog_scans = -1\n"),
		"LiveMapping"));
	EXPECT_ANY_THROW(p.loadFromConfigFile(
		mrpt::config::CConfigFileMemory("[LiveMapping]\nsensor_timeout_s = 0\n"),
		"LiveMapping"));
	EXPECT_ANY_THROW(
		p.loadFromConfigFile(mrpt::config::CConfigFileMemory(
								 "[LiveMapping]\nretry_initial_s = 5\nretry_max_s = 1\n"),
							 "LiveMapping"));
	// A failed load leaves the parameters as they were.
	EXPECT_DOUBLE_EQ(p.sensor_timeout_s, TLiveMappingParams().sensor_timeout_s);
}
