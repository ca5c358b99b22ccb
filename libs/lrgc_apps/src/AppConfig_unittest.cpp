/* loadAppConfig(): an .ini of an earlier lrgc still loads, its old key names reported. */
#include "AppConfig.h"

#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/system/string_utils.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <sstream>

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
// defaults (but for the defaults changed since, which the file sets), and one warning per key
// written under its old name, the app's sections included.
TEST(AppConfig, AnOldFullIniGivesTheDefaultsAndAWarningPerOldKey)
{
	const auto cfg = lrgc::apps::loadAppConfig(std::string(LRGC_SOURCE_DIR) +
											   "/tests/data/lrgc-default-7c31216.ini");
	lrgc::apps::TAppConfig expected;
	expected.lrgc.revisits.radius_m = 1.0;      // 2 m since stop 35 (RevisitLinkerParams.h)
	expected.lrgc.revisits.min_index_gap = 40;  // 15 since the revisit sweep's checks (recall2)
	// 0.40 since session 64 (the museum, ScanMatcherParams.h)
	expected.lrgc.matcher.wide_min_inlier_fraction = 0.45;
	EXPECT_EQ(saved(cfg), saved(expected));
	EXPECT_EQ(cfg.warnings.size(),
			  lrgc::TLRGCParams::renamedKeys().size() + lrgc::apps::appRenamedKeys().size());
	EXPECT_NE(std::find(cfg.warnings.begin(), cfg.warnings.end(),
						"[Localization] min_inliers is now min_inlier_fraction; read as such "
						"(lrgc-slam --write-default-config FILE writes the current names)"),
			  cfg.warnings.end());
	EXPECT_TRUE(
		lrgc::apps::loadAppConfig(std::string(LRGC_SOURCE_DIR) + "/share/lrgc/lrgc-default.ini")
			.warnings.empty());
}

// What --write-default-config hands a user is at most 40 keys, every one a key the loaders
// know (a misspelt entry of userKeys() would silently drop it), each with a comment; the
// expert file has every key; both are the defaults.
TEST(AppConfig, TheUserFileHasAtMost40KnownKeysAndTheExpertFileAll)
{
	const auto& user = lrgc::apps::userKeys();
	EXPECT_LE(user.size(), 40u);
	const mrpt::config::CConfigFileMemory expert(lrgc::apps::expertAppConfigText());
	const mrpt::config::CConfigFileMemory brief(lrgc::apps::defaultAppConfigText());
	size_t briefKeys = 0;
	std::vector<std::string> sections;
	brief.getAllSections(sections);
	for (const auto& s : sections)
	{
		std::vector<std::string> keys;
		brief.getAllKeys(s, keys);
		briefKeys += keys.size();
	}
	EXPECT_EQ(briefKeys, user.size());
	for (const auto& [section, key] : user)
		EXPECT_TRUE(expert.keyExists(section, key)) << section << " " << key;
	std::istringstream briefText(lrgc::apps::defaultAppConfigText());
	for (std::string line; std::getline(briefText, line);)
	{
		if (line.find('=') != std::string::npos)
		{
			EXPECT_NE(line.find(" // "), std::string::npos) << line << ": no one-line meaning";
		}
	}
	// Both texts load (no unknown key, no old name) and give the defaults.
	const auto loaded = [](const std::string& text)
	{
		const std::string path = std::string(LRGC_BINARY_DIR) + "/appconfig_unittest.ini";
		std::ofstream(path) << text;
		return lrgc::apps::loadAppConfig(path);
	};
	for (const auto& text :
		 {lrgc::apps::defaultAppConfigText(), lrgc::apps::expertAppConfigText()})
	{
		const auto cfg = loaded(text);
		EXPECT_TRUE(cfg.warnings.empty());
		EXPECT_EQ(saved(cfg), saved(lrgc::apps::TAppConfig()));
	}
}

// doc/parameters.md has a row for every key of every section (it says why each has its value).
TEST(AppConfig, ParametersDocListsEveryKey)
{
	std::ifstream in(std::string(LRGC_SOURCE_DIR) + "/doc/parameters.md");
	const std::string doc((std::istreambuf_iterator<char>(in)),
						  std::istreambuf_iterator<char>());
	ASSERT_FALSE(doc.empty());
	const mrpt::config::CConfigFileMemory expert(lrgc::apps::expertAppConfigText());
	std::vector<std::string> sections;
	expert.getAllSections(sections);
	for (const auto& section : sections)
	{
		const size_t from = doc.find("## [" + section + "]");
		ASSERT_NE(from, std::string::npos) << section;
		const std::string part = doc.substr(from, doc.find("\n## ", from + 1) - from);
		std::vector<std::string> keys;
		expert.getAllKeys(section, keys);
		for (const auto& key : keys)
			EXPECT_NE(part.find("| `" + mrpt::system::trim(key) + "`"), std::string::npos)
				<< "doc/parameters.md has no row for [" << section << "] " << key;
	}
}

namespace
{
// loadAppConfig's error message for an .ini holding `text` (written as FILE), "" if it loads.
std::string configError(const std::string& name, const std::string& text)
{
	const std::string path = std::string(LRGC_BINARY_DIR) + "/" + name;
	std::ofstream(path, std::ios::binary) << text;
	try
	{
		lrgc::apps::loadAppConfig(path);
	}
	catch (const std::exception& e)
	{
		return e.what();
	}
	return "";
}
}  // namespace

// Issue 30: a key before the first [section] was ignored without a word (MRPT files it under
// section "", which no loader reads).
TEST(AppConfig, AKeyBeforeTheFirstSectionIsAnErrorNamingItsLine)
{
	const std::string msg =
		configError("presection.ini", "# tuned\nkeyframe_distance_m = 0.4\n[MapBuilder]\n");
	EXPECT_NE(msg.find("presection.ini:2: 'keyframe_distance_m = 0.4' comes before the first "
					   "[section]"),
			  std::string::npos)
		<< msg;
	EXPECT_EQ(configError("comments.ini", "; a\n// b\n\n[MapBuilder]\nloop_closing = no\n"),
			  "");
}

// Issue 30: a UTF-8 byte order mark (some editors write one) is no part of the first line:
// the file loads, and an error still names its line.
TEST(AppConfig, AUtf8ByteOrderMarkIsAccepted)
{
	const std::string bom = "\xEF\xBB\xBF";
	const std::string path = std::string(LRGC_BINARY_DIR) + "/bom.ini";
	std::ofstream(path, std::ios::binary) << bom << "[MapBuilder]\nkeyframe_distance_m = 0.4\n";
	EXPECT_EQ(lrgc::apps::loadAppConfig(path).lrgc.builder.keyframe_distance_m, 0.4);
	const std::string msg =
		configError("bom-bad.ini", bom + "[MapBuilder]\nkeyframe_distance_m = abc\n");
	EXPECT_NE(msg.find("bom-bad.ini:2: Invalid value for [MapBuilder] keyframe_distance_m"),
			  std::string::npos)
		<< msg;
	EXPECT_NE(configError("bom-key.ini", bom + "keyframe_distance_m = 0.4\n[MapBuilder]\n")
				  .find("bom-key.ini:1: 'keyframe_distance_m = 0.4' comes before"),
			  std::string::npos);
}

// Issue 30: --config naming a folder said "no such file".
TEST(AppConfig, AFolderIsNamedAsOne)
{
	std::string msg;
	try
	{
		lrgc::apps::loadAppConfig(std::string(LRGC_BINARY_DIR));
	}
	catch (const std::exception& e)
	{
		msg = e.what();
	}
	EXPECT_NE(msg.find("' is a folder; name an .ini file in it"), std::string::npos) << msg;
}
