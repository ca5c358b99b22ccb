/* End to end: a full disk at any point of lrgc-slam's writing never leaves a broken file under
 * a final name and never replaces a good earlier file (issue 30).
 *
 * The failure is injected by tests/fault/write_fault_shim.cpp (LD_PRELOAD): after N bytes
 * written under the output folder, write(2) fails with ENOSPC. N is swept over the whole
 * output of a run (every output, --save-rawlog included): in a fresh folder every file present
 * afterwards must equal the complete run's file, in a folder holding a complete earlier run
 * every file must still be there, complete. The run must fail, naming a file and the cause.
 * The log is made by the tests (room_log.h). */
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>

#include "app_runner.h"
#include "io_test_files.h"
#include "room_log.h"
#include "test_data.h"

namespace fs = std::filesystem;
using namespace lrgc::test;

namespace
{
const std::vector<std::string> kOutputs = {"map.gridmap.gz",
										   "map.png",
										   "map.pgm",
										   "map.yaml",
										   "map.simplemap.gz",
										   "trajectory.tum",
										   "graph.graph",
										   "graph.lrgc",
										   "timing.csv",
										   "stats.json",
										   "log.rawlog",
										   "config.ini",
										   "map.3Dscene",
										   "pf-localization.ini",
										   "observations2map.ini"};

// Files whose content holds measured times: compared by their shape, not their bytes.
/** Outputs whose text differs from run to run: times, or the run's own folder in its paths. */
bool holdsTimes(const std::string& name)
{
	return name == "timing.csv" || name == "stats.json" || name == "pf-localization.ini" ||
		   name == "observations2map.ini";
}

size_t lineCount(const std::string& text)
{
	return std::count(text.begin(), text.end(), '\n');
}

class DiskFull : public ::testing::Test
{
protected:
	void SetUp() override
	{
		m_dir = makeTempDir("disk_full_" + std::to_string(::getpid()));
		m_log = m_dir + "/room.clf";
		writeTextFile(m_log, roomLog());
		m_good = m_dir + "/good";
		const auto r = run(m_good, -1);
		ASSERT_EQ(r.exitCode, 0) << r.output;
		for (const auto& name : kOutputs)
		{
			m_goodFiles[name] = readFileBytes(m_good + "/" + name);
			m_totalBytes += m_goodFiles[name].size();
		}
	}

	// lrgc-slam into `out` (created), failing writes after `failAfter` bytes (-1: never).
	TProcessResult run(const std::string& out, long long failAfter, const char* fsync = "")
	{
		fs::create_directories(out);
		return runProcess(
			"/usr/bin/env",
			{"LD_PRELOAD=" LRGC_WRITE_FAULT_SHIM, "LRGC_FAULT_DIR=" + out + "/",
			 "LRGC_FAULT_WRITE_AFTER=" + std::to_string(failAfter),
			 std::string("LRGC_FAULT_FSYNC=") + fsync, binaryPath("lrgc-slam"), "--input",
			 m_log, "--out", out, "--save-rawlog", out + "/log.rawlog", "--quiet"});
	}

	// Every file in `out` is a complete output (equal to the good run's; for the timed ones,
	// the same number of lines and a JSON object closed), and no temporary is left.
	void expectOnlyCompleteFiles(const std::string& out, bool allPresent,
								 const std::string& what)
	{
		for (const auto& entry : fs::directory_iterator(out))
		{
			const std::string name = entry.path().filename().string();
			ASSERT_TRUE(m_goodFiles.count(name)) << what << ": stray file " << name;
			const std::string bytes = readFileBytes(entry.path().string());
			const std::string& good = m_goodFiles[name];
			if (!holdsTimes(name))
				EXPECT_TRUE(bytes == good) << what << ": " << name << " has " << bytes.size()
										   << " bytes, not the complete file's " << good.size();
			else
				EXPECT_TRUE(lineCount(bytes) == lineCount(good) &&
							bytes.substr(bytes.size() > 2 ? bytes.size() - 2 : 0) ==
								good.substr(good.size() - 2))
					<< what << ": " << name << " is cut short:\n"
					<< bytes;
		}
		if (!allPresent) return;
		for (const auto& name : kOutputs)
			EXPECT_TRUE(fs::exists(out + "/" + name)) << what << ": " << name << " was lost";
	}

	void copyGoodInto(const std::string& out)
	{
		fs::create_directories(out);
		for (const auto& name : kOutputs) fs::copy_file(m_good + "/" + name, out + "/" + name);
	}

	std::string m_dir, m_log, m_good;
	std::map<std::string, std::string> m_goodFiles;
	size_t m_totalBytes = 0;
};
}  // namespace

TEST_F(DiskFull, NoBrokenFileAtAnyFailurePoint)
{
	// 0, a few bytes, then 40 points across the whole output; even steps into a fresh
	// folder, odd ones into a folder holding a complete earlier run.
	std::vector<long long> points = {0, 1, 100};
	for (int k = 1; k < 40; ++k)
		points.push_back(static_cast<long long>(m_totalBytes * k / 40));
	for (size_t i = 0; i < points.size(); ++i)
	{
		const bool earlierRun = i % 2 == 1;
		const std::string out = m_dir + "/sweep" + std::to_string(i);
		if (earlierRun) copyGoodInto(out);
		const std::string what = "fail after " + std::to_string(points[i]) + " of " +
								 std::to_string(m_totalBytes) + " bytes" +
								 (earlierRun ? " (over an earlier run)" : "");
		const auto r = run(out, points[i]);
		EXPECT_NE(r.exitCode, 0) << what << ": " << r.output;
		EXPECT_NE(r.output.find("No space left on device"), std::string::npos)
			<< what << ": " << r.output;
		EXPECT_NE(r.output.find(out + "/"), std::string::npos)
			<< what << ": names no file: " << r.output;
		expectOnlyCompleteFiles(out, earlierRun, what);
		if (HasFailure()) break;  // one point's story is enough
	}
}

TEST_F(DiskFull, FailedFsyncPublishesNothing)
{
	const std::string out = m_dir + "/fsync";
	copyGoodInto(out);
	const auto r = run(out, -1, "EIO");
	EXPECT_NE(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("Input/output error"), std::string::npos) << r.output;
	expectOnlyCompleteFiles(out, true, "fsync fails with EIO");
}
