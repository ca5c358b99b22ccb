/* config.ini in the output folder records the configuration a run used: a run with
 * --config OUT/config.ini repeats it, trajectory byte for byte (SENA; skips where Debian's
 * mrpt-common dataset is absent). */
#include <gtest/gtest.h>

#include <unistd.h>

#include <string>

#include "app_runner.h"
#include "test_data.h"

using namespace lrgc::test;

TEST(SlamConfigIni, OutputFolderConfigRepeatsTheRun)
{
	LRGC_SKIP_IF_MISSING(senaRawlogPath());
	const std::string dir = makeTempDir("config_ini_" + std::to_string(::getpid()));
	// Not the defaults: the keys of the --config .ini must reach config.ini.
	writeTextFile(dir + "/mine.ini",
				  "[MapBuilder]\nkeyframe_distance_m = 0.45\nmax_range_m = 30.5\n");
	auto r = runProcess(binaryPath("lrgc-slam"),
						{"--input", senaRawlogPath(), "--config", dir + "/mine.ini", "--out",
						 dir + "/first", "--quiet"});
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const std::string ini = readTextFile(dir + "/first/config.ini");
	EXPECT_NE(ini.find("[LoopCloser]"), std::string::npos) << ini;  // every section
	EXPECT_NE(ini.find("[LogReader]"), std::string::npos) << ini;
	const auto valueOf = [&](const std::string& key)
	{
		const size_t at = ini.find("\n" + key + " ");
		if (at == std::string::npos) return std::string("(missing)");
		const size_t eq = ini.find('=', at);
		const size_t end = ini.find_first_of("/\n", eq);
		const std::string v = ini.substr(eq + 1, end - eq - 1);
		return v.substr(v.find_first_not_of(' '),
						v.find_last_not_of(' ') - v.find_first_not_of(' ') + 1);
	};
	EXPECT_EQ(valueOf("keyframe_distance_m"), "0.45");  // full precision, shortest text
	EXPECT_EQ(valueOf("max_range_m"), "30.5");

	r = runProcess(binaryPath("lrgc-slam"),
				   {"--input", senaRawlogPath(), "--config", dir + "/first/config.ini", "--out",
					dir + "/again", "--quiet"});
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const std::string first = readTextFile(dir + "/first/trajectory.tum");
	EXPECT_GT(first.size(), 1000u);
	EXPECT_EQ(readTextFile(dir + "/again/trajectory.tum"), first);
	EXPECT_EQ(readTextFile(dir + "/again/config.ini"), ini);
	// A different configuration gives a different map: the comparison above can fail.
	r = runProcess(binaryPath("lrgc-slam"),
				   {"--input", senaRawlogPath(), "--out", dir + "/defaults", "--quiet"});
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(readTextFile(dir + "/defaults/trajectory.tum"), first);
}
