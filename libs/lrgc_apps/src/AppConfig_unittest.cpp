/* loadAppConfig(): an .ini of an earlier lrgc still loads, its old key names reported. */
#include "lrgc_apps/AppConfig.h"

#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

namespace
{
std::string saved(const lrgc::apps::TAppConfig& cfg)
{
	mrpt::config::CConfigFileMemory mem;
	cfg.lrgc.saveToConfigFile(mem, {});
	cfg.reader.saveToConfigFile(mem, "LogReader");
	cfg.live.saveToConfigFile(mem, "LiveMapping");
	cfg.localization.saveToConfigFile(mem, "Localization");
	return mem.getContent();
}
}  // namespace

// share/lrgc/lrgc-default.ini as it was at 7c31216 (every key, before the renames): the
// defaults, and one warning per key written under its old name, the app's sections included.
TEST(AppConfig, AnOldFullIniGivesTheDefaultsAndAWarningPerOldKey)
{
	const auto cfg = lrgc::apps::loadAppConfig(
		std::string(LRGC_SOURCE_DIR) + "/tests/data/lrgc-default-7c31216.ini");
	EXPECT_EQ(saved(cfg), saved(lrgc::apps::TAppConfig()));
	EXPECT_EQ(cfg.warnings.size(), lrgc::TLRGCParams::renamedKeys().size() +
									   lrgc::apps::appRenamedKeys().size());
	EXPECT_NE(std::find(cfg.warnings.begin(), cfg.warnings.end(),
						"[Localization] min_inliers is now min_inlier_fraction; read as such "
						"(lrgc-slam --write-default-config FILE writes the current names)"),
			  cfg.warnings.end());
	EXPECT_TRUE(lrgc::apps::loadAppConfig(std::string(LRGC_SOURCE_DIR) +
										  "/share/lrgc/lrgc-default.ini")
					.warnings.empty());
}
