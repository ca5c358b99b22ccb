/* End to end: what lrgc-slam says. Every error is one line (program, file or option, what is
 * wrong, what to do) without MRPT's banner and call stack, which --verbose adds; a config is
 * never written over an existing file without --force, nor onto a folder; --help lists every
 * option; an interrupted run shows how far it got, not 100 %. (What the loop count counts:
 * SenaRun.ConsoleSaysWhatTheCountsCount, slam_outputs_test.cpp.) */
#include <gtest/gtest.h>

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <set>
#include <thread>

#include "app_runner.h"
#include "child_process.h"
#include "test_data.h"

namespace fs = std::filesystem;
using namespace lrgc::test;

namespace
{
size_t messageLineCount(const std::string& s)
{
	return std::count(s.begin(), s.end(), '\n');
}

// What MRPT's exception texts look like; none of it may reach a user without --verbose.
void expectNoBannerNorBacktrace(const std::string& output)
{
	for (const char* noise : {"====", "exception", "Call stack", "Location:", "Message:"})
		EXPECT_EQ(output.find(noise), std::string::npos) << noise << " in:\n" << output;
}

std::set<std::string> namesIn(const std::string& dir)
{
	std::set<std::string> names;
	for (const auto& e : fs::directory_iterator(dir))
		names.insert(e.path().filename().string());
	return names;
}

// Whether `pid` takes `sig` itself (a handler, or blocked for its signal-watcher thread)
// rather than dying of it.
bool takesSignal(pid_t pid, int sig)
{
	const TSignalDisposition d = signalDisposition(pid, sig);
	return d.caught || d.blockedInMain;
}
}  // namespace

TEST(SlamMessages, ConfigErrorsAreOneLineNamingFileKeyAndWhatToDo)
{
	const std::string dir = makeTempDir("msg_config");
	struct TCase
	{
		std::string ini;
		std::vector<std::string> expected;
	};
	for (const TCase& c :
		 {TCase{"[MapBuilder]\nkeyframe_distanse = 0.5\n",
				{"lrgc-slam: " + dir +
					 "/bad.ini:2: Unknown key 'keyframe_distanse' in section "
					 "[MapBuilder] (did you mean 'keyframe_distance_m'?)",
				 "--write-default-config"}},
		  TCase{"# tuned\n\n[ScanMatcherr]\n",
				{dir + "/bad.ini:3: ", "ScanMatcherr", "--write-default-config"}},
		  // The line of the key in its section, not of the same key in another section.
		  TCase{
			  "[LoopCloser]\n; note\n[MapBuilder]\nmin_scan_points = 20\n"
			  "keyframe_distance_m = abc\n",
			  {dir + "/bad.ini:5: Invalid value for [MapBuilder] keyframe_distance_m: 'abc' is "
					 "not a number"}},
		  // Found by fuzz/fuzz_ini: MRPT's parser throws on an unclosed ${ / $env{ (even in a
		  // comment); that was an exit status 1 with no file named.
		  TCase{"[MapBuilder]\nkeyframe_distance_m = 0.3 // see $env{HOME\n",
				{"lrgc-slam: " + dir + "/bad.ini:2: Expected closing `}`",
				 "--write-default-config"}}})
	{
		writeTextFile(dir + "/bad.ini", c.ini);
		// The configuration is read before the log is opened: the input need not exist.
		const auto r =
			runProcess(binaryPath("lrgc-slam"), {"--input", dir + "/none.rawlog", "--config",
												 dir + "/bad.ini", "--out", dir + "/out"});
		EXPECT_EQ(r.exitCode, 2) << r.output;
		EXPECT_EQ(messageLineCount(r.output), 1u) << r.output;
		for (const auto& text : c.expected)
			EXPECT_NE(r.output.find(text), std::string::npos) << text << " in:\n" << r.output;
		expectNoBannerNorBacktrace(r.output);
	}
	const auto r =
		runProcess(binaryPath("lrgc-slam"), {"--input", dir + "/none.rawlog", "--config",
											 dir + "/missing.ini", "--out", dir + "/out"});
	EXPECT_EQ(r.exitCode, 2) << r.output;
	EXPECT_EQ(messageLineCount(r.output), 1u) << r.output;
	EXPECT_NE(r.output.find("--config '" + dir + "/missing.ini': no such file"),
			  std::string::npos)
		<< r.output;
	EXPECT_FALSE(fs::exists(dir + "/out"));
}

TEST(SlamMessages, VerboseAddsTheDetails)
{
	const std::string dir = makeTempDir("msg_verbose");
	writeTextFile(dir + "/bad.ini", "[MapBuilder]\nkeyframe_distanse = 0.5\n");
	const std::vector<std::string> args = {
		"--input", dir + "/none.rawlog", "--config", dir + "/bad.ini", "--out", dir + "/out"};
	const auto plain = runProcess(binaryPath("lrgc-slam"), args);
	auto verboseArgs = args;
	verboseArgs.push_back("--verbose");
	const auto verbose = runProcess(binaryPath("lrgc-slam"), verboseArgs);
	EXPECT_EQ(verbose.exitCode, 2) << verbose.output;
	// The same first line, then MRPT's account: message, source location, call stack.
	EXPECT_EQ(verbose.output.substr(0, plain.output.size()), plain.output) << verbose.output;
	EXPECT_NE(verbose.output.find("==== MRPT exception ===="), std::string::npos)
		<< verbose.output;
	EXPECT_NE(verbose.output.find("Call stack backtrace"), std::string::npos) << verbose.output;
	EXPECT_NE(verbose.output.find("params_io.cpp"), std::string::npos) << verbose.output;
}

TEST(SlamMessages, InputErrorsAreOneLineWithoutBanner)
{
	const std::string dir = makeTempDir("msg_input");
	auto r = runProcess(binaryPath("lrgc-slam"),
						{"--input", dir + "/nope.rawlog", "--out", dir + "/out"});
	EXPECT_EQ(r.exitCode, 1) << r.output;
	EXPECT_EQ(r.output, "lrgc-slam: " + dir + "/nope.rawlog: cannot open: no such file\n");

	// A rawlog cut short: the run stops at the damage, saves what it mapped, and says where in
	// one line, in the console and in stats.json.
	LRGC_SKIP_IF_MISSING(senaRawlogPath());
	const std::string plain = dir + "/sena.rawlog";
	ASSERT_EQ(
		runProcess("/bin/sh", {"-c", "gzip -dc < \"$0\" > \"$1\"", senaRawlogPath(), plain})
			.exitCode,
		0);
	fs::resize_file(plain, fs::file_size(plain) / 2);
	r = runProcess(binaryPath("lrgc-slam"),
				   {"--input", plain, "--out", dir + "/out", "--quiet"});
	EXPECT_EQ(r.exitCode, 1) << r.output;
	EXPECT_NE(r.output.find("lrgc-slam: input error: " + plain + ": byte "), std::string::npos)
		<< r.output;
	expectNoBannerNorBacktrace(r.output);
	const std::string stats = readTextFile(dir + "/out/stats.json");
	EXPECT_NE(stats.find("\"status\": \"input error: " + plain + ": byte "), std::string::npos)
		<< stats;
	expectNoBannerNorBacktrace(stats);
}

// An .ini of an earlier lrgc (tests/data: the full default file at 7c31216) is read, each key
// written under its old name reported once as a warning naming the new one, all of them
// shown (they do not use up the log's warning budget), before the run starts.
TEST(SlamMessages, OldKeyNamesAreWarningsNamingTheNewKey)
{
	const std::string dir = makeTempDir("msg_old_keys");
	const auto r =
		runProcess(binaryPath("lrgc-slam"),
				   {"--input", dir + "/nope.rawlog", "--out", dir + "/out", "--config",
					std::string(LRGC_SOURCE_DIR) + "/tests/data/lrgc-default-7c31216.ini"});
	EXPECT_EQ(r.exitCode, 1) << r.output;
	EXPECT_NE(
		r.output.find("warning: [MapBuilder] keyframe_distance is now keyframe_distance_m; "
					  "read as such (lrgc-slam --write-default-config FILE writes the "
					  "current names)\n"),
		std::string::npos)
		<< r.output;
	EXPECT_NE(
		r.output.find("warning: [LoopCloser] apply_when_ready is no longer a key: ignored"),
		std::string::npos)
		<< r.output;
	EXPECT_EQ(messageLineCount(r.output), 51u)
		<< r.output;  // 50 old keys, then the input's error
	EXPECT_EQ(r.output.find("further warnings"), std::string::npos) << r.output;
}

TEST(SlamMessages, WriteDefaultConfigOntoAFolderIsRefusedInOneLine)
{
	const std::string dir = makeTempDir("msg_config_folder");
	fs::create_directory(dir + "/conf");
	const auto before = namesIn(dir);
	for (const std::string& target : {dir + "/conf", dir + "/conf/"})
	{
		for (const bool force : {false, true})
		{
			std::vector<std::string> args = {"--write-default-config", target};
			if (force) args.push_back("--force");
			const auto r = runProcess(binaryPath("lrgc-slam"), args);
			EXPECT_EQ(r.exitCode, 2) << r.output;
			EXPECT_EQ(messageLineCount(r.output), 1u) << r.output;
			EXPECT_NE(r.output.find("is a directory; name a file"), std::string::npos)
				<< r.output;
			expectNoBannerNorBacktrace(r.output);
		}
	}
	// Nothing written beside it (the temporary file used to land in the folder's parent).
	EXPECT_EQ(namesIn(dir), before);
	EXPECT_TRUE(fs::is_empty(dir + "/conf"));

	const auto r = runProcess(binaryPath("lrgc-slam"),
							  {"--write-default-config", dir + "/missing/lrgc.ini"});
	EXPECT_EQ(r.exitCode, 2) << r.output;
	EXPECT_EQ(messageLineCount(r.output), 1u) << r.output;
	EXPECT_NE(r.output.find("'" + dir + "/missing' is not a directory"), std::string::npos)
		<< r.output;
}

TEST(SlamMessages, WriteDefaultConfigReplacesAFileOnlyWithForce)
{
	const std::string dir = makeTempDir("msg_config_force");
	const std::string ini = dir + "/my.ini";
	const std::string tuned = "[MapBuilder]\nkeyframe_distance_m = 0.4\n";
	writeTextFile(ini, tuned);
	auto r = runProcess(binaryPath("lrgc-slam"), {"--write-default-config", ini});
	EXPECT_EQ(r.exitCode, 2) << r.output;
	EXPECT_EQ(r.output, "lrgc-slam: --write-default-config '" + ini +
							"': the file exists; add --force to replace it, or name another "
							"file\n");
	EXPECT_EQ(readTextFile(ini), tuned);

	r = runProcess(binaryPath("lrgc-slam"), {"--write-default-config", ini, "--force"});
	EXPECT_EQ(r.exitCode, 0) << r.output;
	EXPECT_EQ(readTextFile(ini),
			  readTextFile(std::string(LRGC_SOURCE_DIR) + "/share/lrgc/lrgc-default.ini"));
	EXPECT_EQ(namesIn(dir), std::set<std::string>{"my.ini"});

	// --force is for the config alone: it does not license anything in a run.
	r = runProcess(binaryPath("lrgc-slam"),
				   {"--input", dir + "/none.rawlog", "--out", dir + "/out", "--force"});
	EXPECT_EQ(r.exitCode, 2) << r.output;
	EXPECT_EQ(messageLineCount(r.output), 1u) << r.output;
}

TEST(SlamMessages, UsageErrorsAreOneLineAndHelpListsEveryOption)
{
	auto r = runProcess(binaryPath("lrgc-slam"), {"--inptu", "x"});
	EXPECT_EQ(r.exitCode, 2) << r.output;
	EXPECT_EQ(r.output,
			  "lrgc-slam: unknown argument '--inptu'; lrgc-slam --help lists the options\n");

	for (const char* bad : {"0", "-1", "ten", "10s", "nan", "inf"})
	{
		r = runProcess(binaryPath("lrgc-slam"),
					   {"--input", "x", "--out", "y", "--progress-interval", bad});
		EXPECT_EQ(r.exitCode, 2) << bad << ": " << r.output;
		EXPECT_EQ(r.output, std::string("lrgc-slam: --progress-interval needs a number of "
										"seconds above 0, not '") +
								bad + "'\n");
	}

	r = runProcess(binaryPath("lrgc-slam"), {"--help"});
	EXPECT_EQ(r.exitCode, 0) << r.output;
	for (const char* option : {"--input", "--config", "--out", "--quiet", "--save-rawlog",
							   "--live", "--write-default-config", "--force", "--verbose",
							   "--help", "--version", "--progress-interval"})
		EXPECT_NE(r.output.find(option), std::string::npos) << option << " not in:\n"
															<< r.output;
	// The synopsis (the lines before "Options:") shows --laser with the runs that take it.
	const std::string synopsis = r.output.substr(0, r.output.find("Options:"));
	EXPECT_NE(synopsis.find("--input FILE [--config FILE.ini] --out DIR [--laser LABEL]"),
			  std::string::npos)
		<< synopsis;
	EXPECT_NE(synopsis.find("--live SENSORS.ini [--config FILE.ini] --out DIR [--laser LABEL]"),
			  std::string::npos)
		<< synopsis;

	r = runProcess(binaryPath("lrgc-slam"), {"--version"});
	EXPECT_EQ(r.exitCode, 0) << r.output;
	EXPECT_EQ(r.output.rfind("lrgc-slam ", 0), 0u) << r.output;
	EXPECT_EQ(messageLineCount(r.output), 1u) << r.output;
	// Every program answers --version with the same version.
	const std::string version = r.output.substr(std::string("lrgc-slam").size());
	for (const char* program : {"lrgc-eval", "lrgc-plot"})
	{
		const auto v = runProcess(binaryPath(program), {"--version"});
		EXPECT_EQ(v.exitCode, 0) << program << ": " << v.output;
		EXPECT_EQ(v.output, program + version);
	}
}

TEST(SlamMessages, InterruptedRunShowsHowFarItGot)
{
	LRGC_SKIP_IF_MISSING(senaRawlogPath());
	const std::string dir = makeTempDir("msg_interrupted_" + std::to_string(::getpid()));
	CChildProcess app(binaryPath("lrgc-slam"),
					  {"--input", senaRawlogPath(), "--out", dir + "/out"},
					  dir + "/console.txt");
	// SIGINT once the run takes it (its signal watcher starts after the .ini is read).
	const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
	while (!takesSignal(app.pid(), SIGINT) && std::chrono::steady_clock::now() < deadline)
		std::this_thread::sleep_for(std::chrono::milliseconds(1));
	ASSERT_TRUE(takesSignal(app.pid(), SIGINT)) << app.output();
	app.signal(SIGINT);
	const auto status = app.waitExit(120);
	ASSERT_TRUE(status.has_value());
	const std::string out = app.output();
	ASSERT_EQ(*status, 130) << "the run ended before the signal reached it?\n" << out;
	EXPECT_EQ(out.find("100.0%"), std::string::npos) << out;
	EXPECT_NE(out.find("% "), std::string::npos) << out;
	EXPECT_NE(out.find("interrupted"), std::string::npos) << out;
}

// --live runs in lrgc-slam-live, which lrgc-slam execs (LiveProgram.h): found beside it, the
// sensors file is that program's to check; a lrgc-slam without it says so in one line.
TEST(SlamMessages, LiveWithoutTheLiveProgramIsOneLineNamingWhereItLooked)
{
	const std::string dir = makeTempDir("msg_live");
	auto r = runProcess(binaryPath("lrgc-slam"),
						{"--live", dir + "/none.ini", "--out", dir + "/out"});
	EXPECT_EQ(r.exitCode, 2) << r.output;
	EXPECT_EQ(r.output, "lrgc-slam: sensors file '" + dir + "/none.ini' does not exist\n");

	const std::string lonely = dir + "/bin/lrgc-slam";
	fs::create_directories(dir + "/bin");
	fs::copy_file(binaryPath("lrgc-slam"), lonely);
	r = runProcess(lonely, {"--live", dir + "/none.ini", "--out", dir + "/out"});
	EXPECT_EQ(r.exitCode, 2) << r.output;
	// ... and where an install keeps it (../libexec/lrgc with the default install folders).
	EXPECT_EQ(r.output.rfind("lrgc-slam: --live: lrgc-slam-live (live sensor support) is not "
							 "installed: looked for " +
								 dir + "/bin/lrgc-slam-live and ",
							 0),
			  0u)
		<< r.output;
	EXPECT_EQ(messageLineCount(r.output), 1u) << r.output;
	EXPECT_FALSE(fs::exists(dir + "/out"));
}
