/* Format detection by content, and the errors for files that are no log at all. */
#include <gtest/gtest.h>
#include <io_read_all.h>
#include <io_test_files.h>
#include "io/LogInputFile.h"
#include <lrgc_apps/io/LogReader.h>
#include <test_data.h>

#include <random>

using namespace lrgc::apps;
using lrgc::test::contains;

namespace
{
// The CLogReadError message of detectLogFormat (and openLog) on `path`, or "" if none.
std::string detectionError(const std::string& path)
{
	std::string msg;
	try
	{
		detectLogFormat(path);
	}
	catch (const CLogReadError& e)
	{
		msg = e.what();
		EXPECT_EQ(e.file(), path);
	}
	try
	{
		openLog(path);
		EXPECT_TRUE(msg.empty()) << "openLog accepted what detectLogFormat rejected";
	}
	catch (const CLogReadError& e)
	{
		EXPECT_EQ(msg, e.what());
	}
	return msg;
}
}  // namespace

TEST(LogFormat, RejectsAMissingFileNamingIt)
{
	const std::string dir = lrgc::test::makeTempDir("format_missing");
	const std::string path = dir + "/no-such.clf.gz";
	EXPECT_EQ(detectionError(path), path + ": cannot open: no such file");
	EXPECT_EQ(detectionError(dir), dir + ": cannot open: a directory");
}

TEST(LogFormat, RejectsEmptyFilesPlainAndGzip)
{
	const std::string dir = lrgc::test::makeTempDir("format_empty");
	lrgc::test::writeFileBytes(dir + "/empty.rawlog", "");
	EXPECT_EQ(detectionError(dir + "/empty.rawlog"), dir + "/empty.rawlog: empty file");
	lrgc::test::writeGzFile(dir + "/empty.clf.gz", "");
	EXPECT_TRUE(contains(detectionError(dir + "/empty.clf.gz"), "empty log"));
	lrgc::test::writeFileBytes(dir + "/stub.gz", "\x1f\x8b\x08");
	EXPECT_TRUE(contains(detectionError(dir + "/stub.gz"), "gzip file truncated"));
}

TEST(LogFormat, RejectsGarbageSayingWhy)
{
	const std::string dir = lrgc::test::makeTempDir("format_garbage");
	std::mt19937 rng(7);
	std::string noise(5000, '\0');
	for (char& c : noise) c = char(rng());
	noise[0] = 0;  // not a class-name header
	lrgc::test::writeFileBytes(dir + "/noise.rawlog", noise);
	EXPECT_TRUE(contains(detectionError(dir + "/noise.rawlog"), "unknown log format"));
	lrgc::test::writeGzFile(dir + "/noise.gz", noise);
	EXPECT_TRUE(contains(detectionError(dir + "/noise.gz"), "unknown log format"));

	lrgc::test::writeFileBytes(dir + "/prose.clf", "# a comment\nhello world\n");
	EXPECT_TRUE(contains(detectionError(dir + "/prose.clf"),
						 "line 2 starts with 'hello', which is no CARMEN"));
	lrgc::test::writeFileBytes(dir + "/params.clf", "# CARMEN\nPARAM a 1 h 0\nSYNC x\n");
	EXPECT_TRUE(contains(detectionError(dir + "/params.clf"),
						 "no FLASER, RLASER, ROBOTLASER1 or ODOM line"));
}

TEST(LogFormat, DetectsByContentNotByName)
{
	const std::string dir = lrgc::test::makeTempDir("format_content");
	LRGC_SKIP_IF_MISSING(lrgc::test::senaRawlogPath());
	const std::string rawlogAsClf = dir + "/really-a-rawlog.clf";
	lrgc::test::writeFileBytes(rawlogAsClf,
							   lrgc::test::readFileBytes(lrgc::test::senaRawlogPath()));
	EXPECT_EQ(detectLogFormat(rawlogAsClf), LogFormat::MrptRawlog);
	const std::string plainAsGz = dir + "/plain-rawlog.clf.gz";
	lrgc::test::writeFileBytes(plainAsGz,
							   lrgc::test::readUncompressed(lrgc::test::senaRawlogPath()));
	EXPECT_EQ(detectLogFormat(plainAsGz), LogFormat::MrptRawlog);
	const std::string carmenAsRawlog = dir + "/carmen.rawlog";
	lrgc::test::writeFileBytes(carmenAsRawlog,
							   "# CARMEN Logfile\nPARAM x 1 h 0\nODOM 0 0 0 0 0 0 1.5 h 1.5\n");
	EXPECT_EQ(detectLogFormat(carmenAsRawlog), LogFormat::Carmen);
	EXPECT_EQ(openLog(carmenAsRawlog)->format(), LogFormat::Carmen);
	EXPECT_EQ(openLog(rawlogAsClf)->format(), LogFormat::MrptRawlog);
}

TEST(LogInputFile, ComputesTheGzipCrc32)
{
	EXPECT_EQ(crc32Update(0, "123456789", 9), 0xCBF43926u);  // the standard check value
	EXPECT_EQ(crc32Update(crc32Update(0, "1234", 4), "56789", 5), 0xCBF43926u);
	EXPECT_EQ(crc32Update(0, "", 0), 0u);
}

TEST(LogInputFile, CountsUncompressedBytesAndChecksTheTrailer)
{
	const std::string dir = lrgc::test::makeTempDir("input_file");
	std::string text;
	for (int i = 0; i < 20000; ++i) text += "line " + std::to_string(i) + "\n";
	lrgc::test::writeGzFile(dir + "/t.gz", text);
	CLogInputFile in(dir + "/t.gz");
	EXPECT_TRUE(in.isGzip());
	std::string got(text.size() + 10, '\0');
	EXPECT_EQ(in.Read(got.data(), 1000), 1000u);
	EXPECT_EQ(in.position(), 1000u);
	EXPECT_NEAR(in.fractionRead(), 1000.0 / double(text.size()), 1e-12);
	EXPECT_EQ(in.Read(got.data() + 1000, got.size() - 1000), text.size() - 1000);
	EXPECT_TRUE(in.reachedEnd());
	EXPECT_EQ(got.substr(0, text.size()), text);
	EXPECT_NO_THROW(in.verifyCompleteAtEnd());
	EXPECT_DOUBLE_EQ(in.fractionRead(), 1.0);
}
