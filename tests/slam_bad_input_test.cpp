/* End to end: lrgc-slam on bad input says what is wrong and where, exits non-zero where the
 * run cannot go on, and keeps what was mapped so far. */
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "app_runner.h"
#include "test_data.h"

namespace fs = std::filesystem;
using namespace lrgc::test;

TEST(SlamBadInput, MissingInputFileIsNamed)
{
	const std::string dir = makeTempDir("bad_missing");
	const auto r = runProcess(binaryPath("lrgc-slam"),
							  {"--input", dir + "/nope.rawlog", "--out", dir + "/out"});
	EXPECT_EQ(r.exitCode, 1) << r.output;
	EXPECT_NE(r.output.find("nope.rawlog"), std::string::npos) << r.output;
}

TEST(SlamBadInput, SaveRawlogOverTheInputIsRefusedAndTheInputKept)
{
	const std::string dir = makeTempDir("bad_overwrite");
	const std::string input = dir + "/log.clf";
	const std::string content = "# a CARMEN log the user cannot get back\n";
	writeTextFile(input, content);
	fs::create_symlink(input, dir + "/link.clf");
	for (const std::string& target : {input, dir + "/./log.clf", dir + "/link.clf"})
	{
		const auto r =
			runProcess(binaryPath("lrgc-slam"), {"--input", input, "--save-rawlog", target});
		EXPECT_EQ(r.exitCode, 2) << target << ": " << r.output;
		EXPECT_NE(r.output.find("refusing to overwrite"), std::string::npos) << r.output;
		std::ifstream in(input);
		const std::string now((std::istreambuf_iterator<char>(in)),
							  std::istreambuf_iterator<char>());
		EXPECT_EQ(now, content) << "the input was changed by --save-rawlog " << target;
	}
}

TEST(SlamBadInput, SaveRawlogIsCheckedBeforeTheRun)
{
	const std::string dir = makeTempDir("bad_save_rawlog");
	const std::string input = dir + "/log.clf";
	writeTextFile(input, "ODOM 0 0 0 0 0 0 1.0 host 1.0\n");
	fs::create_directories(dir + "/folder");
	struct TCase
	{
		std::string target, expected;
	};
	for (const TCase& c :
		 {TCase{dir + "/folder", "--save-rawlog '" + dir + "/folder' is a directory"},
		  TCase{dir + "/missing/log.rawlog",
				"'" + dir + "/missing' is not a directory; create it first"},
		  TCase{"/dev/null", "--save-rawlog '/dev/null' exists and is not a regular file"},
		  // No one may write into /proc, root included.
		  TCase{"/proc/lrgc.rawlog",
				"--save-rawlog '/proc/lrgc.rawlog': cannot write into "
				"'/proc'"}})
	{
		for (const bool alsoMap : {false, true})
		{
			std::vector<std::string> args = {"--input", input, "--save-rawlog", c.target};
			if (alsoMap) args.insert(args.end(), {"--out", dir + "/out"});
			const auto r = runProcess(binaryPath("lrgc-slam"), args);
			EXPECT_EQ(r.exitCode, 2) << c.target << ": " << r.output;
			EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
			EXPECT_NE(r.output.find(c.expected), std::string::npos) << r.output;
			// Refused before the run: nothing mapped, nothing converted.
			EXPECT_FALSE(fs::exists(dir + "/out")) << c.target;
		}
	}
	EXPECT_TRUE(fs::is_empty(dir + "/folder"));
	EXPECT_TRUE(fs::exists("/dev/null") && !fs::is_regular_file("/dev/null"));
}

TEST(SlamBadInput, UnknownArgumentIsAUsageError)
{
	const auto r = runProcess(binaryPath("lrgc-slam"), {"--inptu", "x"});
	EXPECT_EQ(r.exitCode, 2);
	EXPECT_NE(r.output.find("--inptu"), std::string::npos) << r.output;
}

TEST(SlamBadInput, UnknownIniKeyIsRejectedWithSuggestion)
{
	LRGC_SKIP_IF_MISSING(senaRawlogPath());
	const std::string dir = makeTempDir("bad_ini");
	writeTextFile(dir + "/bad.ini", "[MapBuilder]\nkeyframe_distanse = 0.5\n");
	const auto r = runProcess(
		binaryPath("lrgc-slam"),
		{"--input", senaRawlogPath(), "--config", dir + "/bad.ini", "--out", dir + "/out"});
	EXPECT_EQ(r.exitCode, 2) << r.output;
	EXPECT_NE(r.output.find("keyframe_distanse"), std::string::npos) << r.output;
	EXPECT_NE(r.output.find("keyframe_distance_m"), std::string::npos) << r.output;
	EXPECT_NE(r.output.find("MapBuilder"), std::string::npos) << r.output;
	EXPECT_FALSE(fs::exists(dir + "/out/map.gridmap.gz"));
}

TEST(SlamBadInput, UnknownIniSectionIsRejected)
{
	LRGC_SKIP_IF_MISSING(senaRawlogPath());
	const std::string dir = makeTempDir("bad_section");
	writeTextFile(dir + "/bad.ini", "[ScanMatcherr]\n");
	const auto r = runProcess(
		binaryPath("lrgc-slam"),
		{"--input", senaRawlogPath(), "--config", dir + "/bad.ini", "--out", dir + "/out"});
	EXPECT_EQ(r.exitCode, 2) << r.output;
	EXPECT_NE(r.output.find("ScanMatcherr"), std::string::npos) << r.output;
}

TEST(SlamBadInput, IniValueOfTheWrongTypeNamesKeyValueAndType)
{
	LRGC_SKIP_IF_MISSING(senaRawlogPath());
	struct TCase
	{
		const char *section, *key, *value, *expected;
	};
	// MRPT's readers took each of these silently: "on"/"maybe" as false, "abc"/"0,5" as 0
	// (blamed as "must be > 0"), 12.7 as 12, 2.5 as 2 (blamed on max_pairwise_links).
	for (const TCase& c : {TCase{"MapBuilder", "loop_closing", "on", "a boolean"},
						   TCase{"MapBuilder", "loop_closing", "maybe", "a boolean"},
						   TCase{"MapBuilder", "keyframe_distance_m", "abc", "a number"},
						   TCase{"MapBuilder", "keyframe_distance_m", "0,5", "a number"},
						   TCase{"LocalRegistration", "window_size", "12.7", "a whole number"},
						   TCase{"LocalRegistration", "window_size", "2.5", "a whole number"}})
	{
		const std::string dir = makeTempDir("bad_ini_value");
		writeTextFile(dir + "/bad.ini",
					  std::string("[") + c.section + "]\n" + c.key + " = " + c.value + "\n");
		const auto r = runProcess(
			binaryPath("lrgc-slam"),
			{"--input", senaRawlogPath(), "--config", dir + "/bad.ini", "--out", dir + "/out"});
		EXPECT_EQ(r.exitCode, 2) << r.output;
		const std::string expected = std::string("[") + c.section + "] " + c.key + ": '" +
									 c.value + "' is not " + c.expected;
		EXPECT_NE(r.output.find(expected), std::string::npos) << expected << "\n" << r.output;
		EXPECT_EQ(r.output.find("max_pairwise_links"), std::string::npos) << r.output;
		EXPECT_FALSE(fs::exists(dir + "/out"));
	}
}

TEST(SlamBadInput, BadOutIsRefusedBeforeTheRunInOneLine)
{
	LRGC_SKIP_IF_MISSING(senaRawlogPath());
	const std::string dir = makeTempDir("bad_out");
	writeTextFile(dir + "/file.txt", "not a directory\n");
	struct TCase
	{
		std::string out, expected;
	};
	for (const TCase& c :
		 {TCase{dir + "/file.txt", "--out '" + dir + "/file.txt' is not a directory"},
		  TCase{dir + "/file.txt/maps", "'" + dir + "/file.txt' is not a directory"},
		  TCase{"/dev/null", "--out '/dev/null' is not a directory"},
		  TCase{"/proc/lrgc-maps", "cannot write into '/proc'"}})
	{
		// Found before the input is even opened: a missing input would be exit status 1.
		for (const std::string& input : {senaRawlogPath(), dir + "/missing.rawlog"})
		{
			const auto r =
				runProcess(binaryPath("lrgc-slam"), {"--input", input, "--out", c.out});
			EXPECT_EQ(r.exitCode, 2) << c.out << ": " << r.output;
			EXPECT_NE(r.output.find(c.expected), std::string::npos) << r.output;
			EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
		}
	}
	EXPECT_EQ(readTextFile(dir + "/file.txt"), "not a directory\n");
	EXPECT_TRUE(fs::is_character_file("/dev/null"));
}

TEST(SlamBadInput, OutInAFolderWithoutWritePermissionIsRefused)
{
	LRGC_SKIP_IF_MISSING(senaRawlogPath());
	if (::geteuid() == 0)
		GTEST_SKIP()
			<< "running as root, who may write into a read-only folder (the /proc case "
			   "of BadOutIsRefusedBeforeTheRunInOneLine covers root)";
	const std::string dir = makeTempDir("bad_out_readonly");
	fs::create_directory(dir + "/ro");
	fs::permissions(dir + "/ro", fs::perms::owner_read | fs::perms::owner_exec);
	const auto r = runProcess(binaryPath("lrgc-slam"),
							  {"--input", senaRawlogPath(), "--out", dir + "/ro/maps"});
	fs::permissions(dir + "/ro", fs::perms::owner_all);
	EXPECT_EQ(r.exitCode, 2) << r.output;
	EXPECT_NE(r.output.find("cannot write into '" + dir + "/ro' (Permission denied)"),
			  std::string::npos)
		<< r.output;
}

TEST(SlamBadInput, TruncatedRawlogSavesWhatWasMappedAndFails)
{
	LRGC_SKIP_IF_MISSING(senaRawlogPath());
	const std::string dir = makeTempDir("bad_truncated");
	// The SENA rawlog is gzip-compressed: decompress, cut the stream at 60 %, store plain.
	const std::string plain = dir + "/sena.rawlog";
	ASSERT_EQ(
		runProcess("/bin/sh", {"-c", "gzip -dc < \"$0\" > \"$1\"", senaRawlogPath(), plain})
			.exitCode,
		0);
	const auto size = fs::file_size(plain);
	fs::resize_file(plain, size * 6 / 10);
	const auto r =
		runProcess(binaryPath("lrgc-slam"), {"--input", plain, "--out", dir + "/out"});
	EXPECT_EQ(r.exitCode, 1) << r.output;
	EXPECT_NE(r.output.find("sena.rawlog"), std::string::npos) << r.output;
	EXPECT_NE(r.output.find("byte"), std::string::npos) << r.output;
	ASSERT_TRUE(fs::exists(dir + "/out/map.gridmap.gz"));
	const std::string stats = readTextFile(dir + "/out/stats.json");
	EXPECT_NE(stats.find("\"status\": \"input error"), std::string::npos) << stats;
	// Roughly 60 % of the 225 scans were mapped and kept.
	std::ifstream tum(dir + "/out/trajectory.tum");
	size_t lines = 0;
	for (std::string l; std::getline(tum, l);) ++lines;
	EXPECT_GT(lines, 100u);
	EXPECT_LT(lines, 225u);
}

TEST(SlamConfig, ShippedDefaultIniIsTheGeneratedOne)
{
	const std::string dir = makeTempDir("default_ini");
	for (const std::string kind : {"default", "expert"})
	{
		std::vector<std::string> args = {"--write-default-config", dir + "/" + kind + ".ini"};
		if (kind == "expert") args.push_back("--expert");
		const auto r = runProcess(binaryPath("lrgc-slam"), args);
		ASSERT_EQ(r.exitCode, 0) << r.output;
		const std::string shipped = "share/lrgc/lrgc-" + kind + ".ini";
		EXPECT_EQ(readTextFile(dir + "/" + kind + ".ini"),
				  readTextFile(std::string(LRGC_SOURCE_DIR) + "/" + shipped))
			<< shipped << " is stale: regenerate it with build/bin/lrgc-slam "
			<< "--write-default-config " << shipped << " --force"
			<< (kind == "expert" ? " --expert" : "");
	}
}
