/* The CARMEN reader on files as they come: gzip and plain detected by content, truncated,
 * multi-member, zero-padded and corrupt gzip, a FIFO, a plain log cut inside its last line.
 * Messages, fields and geometry: CarmenReader_unittest.cpp. */
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <io_read_all.h>
#include <io_test_files.h>
#include <lrgc/scan_matching/Scan.h>
#include <lrgc/common/se2.h>
#include <lrgc_apps/io/LogReader.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <test_data.h>

#include "CarmenReader_unittest.h"

#include <cmath>

using namespace lrgc::apps;
using namespace lrgc::apps::test;
using lrgc::test::anyContains;
using lrgc::test::contains;
using lrgc::test::readWholeLog;
using mrpt::math::TPose2D;
using mrpt::obs::CObservation2DRangeScan;
using mrpt::obs::CObservationOdometry;

TEST(CarmenReader, ReadsGzipAndPlainAlikeAndDetectsByContent)
{
	const std::string dir = lrgc::test::makeTempDir("carmen_gz");
	const std::string text = basicLog();
	const std::string plain = writeLog(dir, "log.clf", text);
	// Misleading names: a gzip CARMEN log called .rawlog, a plain one called .gz.
	const std::string gz = dir + "/looks-like.rawlog";
	lrgc::test::writeGzFile(gz, text);
	const std::string odd = writeLog(dir, "not-compressed.gz", text);
	EXPECT_EQ(detectLogFormat(gz), LogFormat::Carmen);
	EXPECT_EQ(detectLogFormat(odd), LogFormat::Carmen);
	const auto a = readWholeLog(plain), b = readWholeLog(gz), c = readWholeLog(odd);
	ASSERT_FALSE(b.error) << *b.error;
	ASSERT_FALSE(c.error) << *c.error;
	ASSERT_EQ(a.entries.size(), b.entries.size());
	ASSERT_EQ(a.entries.size(), c.entries.size());
	for (size_t i = 0; i < a.entries.size(); ++i)
	{
		EXPECT_EQ(a.entries[i].observation->timestamp, b.entries[i].observation->timestamp);
		EXPECT_EQ(a.entries[i].observation->sensorLabel, b.entries[i].observation->sensorLabel);
		const auto sa = as<CObservation2DRangeScan>(a.entries[i]);
		const auto sb = as<CObservation2DRangeScan>(b.entries[i]);
		if (sa)
		{
			EXPECT_EQ(sa->getScanRange(7), sb->getScanRange(7));
		}
	}
	// Progress: non-decreasing, 1 at the end.
	for (size_t i = 1; i < b.fractions.size(); ++i)
		EXPECT_GE(b.fractions[i], b.fractions[i - 1]);
	EXPECT_DOUBLE_EQ(b.fractions.back(), 1.0);
}

TEST(CarmenReader, TruncatedGzipFailsAfterReturningEveryCompleteLine)
{
	const std::string dir = lrgc::test::makeTempDir("carmen_gz_truncated");
	const TPose2D p{0, 0, 0};
	std::string text;
	for (int k = 0; k < 400; ++k)
		text += lrgc::test::flaserLine(ramp(180, 1 + 0.001 * k, 0.013), p, p, kT0 + 0.1 * k);
	const std::string full = dir + "/full.clf.gz";
	lrgc::test::writeGzFile(full, text);
	const auto whole = readWholeLog(full);
	ASSERT_FALSE(whole.error);
	ASSERT_EQ(whole.stats.scans, 400u);
	const std::string bytes = lrgc::test::readFileBytes(full);
	for (const size_t cut : {bytes.size() / 4, bytes.size() / 2, bytes.size() - 9,
							 bytes.size() - 4, bytes.size() - 1})
	{
		const std::string path = dir + "/cut" + std::to_string(cut) + ".clf.gz";
		lrgc::test::writeFileBytes(path, bytes.substr(0, cut));
		const auto r = readWholeLog(path);
		ASSERT_TRUE(r.error) << "cut at " << cut << " went unnoticed";
		EXPECT_TRUE(contains(*r.error, path + ": byte ")) << *r.error;
		EXPECT_TRUE(contains(*r.error, "truncated or corrupt")) << *r.error;
		// Every entry returned is the one of the complete file, in order.
		ASSERT_LE(r.entries.size(), whole.entries.size());
		for (size_t i = 0; i < r.entries.size(); ++i)
			ASSERT_EQ(r.entries[i].observation->timestamp,
					  whole.entries[i].observation->timestamp);
		if (cut > bytes.size() / 2)
		{
			EXPECT_GT(r.stats.scans, 150u) << cut;
		}
	}
}

// Issue 30: a valid multi-member gzip log (`cat a.gz b.gz`) or one with zero padding after
// its member was mapped, then reported "truncated or corrupt". Both read whole now; a
// multi-member log cut short, or with data after the padding, still fails.
TEST(CarmenReader, MultiMemberAndZeroPaddedGzipReadWhole)
{
	const std::string dir = lrgc::test::makeTempDir("carmen_gz_members");
	const TPose2D p{0, 0, 0};
	std::string first, second;
	for (int k = 0; k < 200; ++k)
		(k < 100 ? first : second) +=
			lrgc::test::flaserLine(ramp(180, 1 + 0.001 * k, 0.013), p, p, kT0 + 0.1 * k);
	lrgc::test::writeGzFile(dir + "/a.gz", first);
	lrgc::test::writeGzFile(dir + "/b.gz", second);
	const std::string a = lrgc::test::readFileBytes(dir + "/a.gz");
	const std::string b = lrgc::test::readFileBytes(dir + "/b.gz");
	const auto readAs = [&](const std::string& name, const std::string& bytes)
	{
		lrgc::test::writeFileBytes(dir + "/" + name, bytes);
		return readWholeLog(dir + "/" + name);
	};
	const auto both = readAs("both.clf.gz", a + b);
	ASSERT_FALSE(both.error) << *both.error;
	EXPECT_EQ(both.stats.scans, 200u);
	const auto padded = readAs("padded.clf.gz", a + std::string(512, '\0'));
	ASSERT_FALSE(padded.error) << *padded.error;
	EXPECT_EQ(padded.stats.scans, 100u);
	const auto bothPadded = readAs("both-padded.clf.gz", a + b + std::string(3, '\0'));
	ASSERT_FALSE(bothPadded.error) << *bothPadded.error;
	EXPECT_EQ(bothPadded.stats.scans, 200u);
	for (const auto& [name, bytes] :
		 {std::pair<std::string, std::string>{"cut.clf.gz", a + b.substr(0, b.size() - 5)},
		  {"garbage.clf.gz", a + std::string(4, '\0') + b}})
	{
		const auto r = readAs(name, bytes);
		ASSERT_TRUE(r.error) << name << " went unnoticed";
		EXPECT_TRUE(contains(*r.error, "truncated or corrupt")) << *r.error;
	}
}

// Issue 30: a FIFO failed with "cannot get its size" and no hint.
TEST(CarmenReader, FifoIsRefusedSayingWhatToDo)
{
	const std::string fifo = lrgc::test::makeTempDir("carmen_fifo") + "/log.clf";
	ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
	const auto r = readWholeLog(fifo);
	ASSERT_TRUE(r.error);
	EXPECT_TRUE(contains(*r.error, "not a regular file")) << *r.error;
	EXPECT_TRUE(contains(*r.error, "save the stream to a file first")) << *r.error;
}

TEST(CarmenReader, CorruptGzipFailsNamingTheByte)
{
	const std::string dir = lrgc::test::makeTempDir("carmen_gz_corrupt");
	const TPose2D p{0, 0, 0};
	std::string text;
	for (int k = 0; k < 200; ++k)
		text += lrgc::test::flaserLine(ramp(180, 1 + 0.001 * k, 0.013), p, p, kT0 + 0.1 * k);
	const std::string full = dir + "/full.clf.gz";
	lrgc::test::writeGzFile(full, text);
	std::string bytes = lrgc::test::readFileBytes(full);
	for (size_t i = bytes.size() / 2; i < bytes.size() / 2 + 16; ++i) bytes[i] ^= 0x5A;
	const std::string path = dir + "/corrupt.clf.gz";
	lrgc::test::writeFileBytes(path, bytes);
	const auto r = readWholeLog(path);
	ASSERT_TRUE(r.error);
	EXPECT_TRUE(contains(*r.error, path + ": byte ")) << *r.error;
	EXPECT_TRUE(contains(*r.error, "corrupt")) << *r.error;
}

TEST(CarmenReader, WarnsAboutAPlainLogCutInsideItsLastLine)
{
	const std::string dir = lrgc::test::makeTempDir("carmen_plain_truncated");
	const TPose2D p{0, 0, 0};
	const std::string a = lrgc::test::flaserLine({1, 2, 3}, p, p, kT0);
	const std::string b = lrgc::test::flaserLine({1, 2, 3}, p, p, kT0 + 1);
	// Cut inside the ranges, inside the timestamp (would parse, with a wrong time), and
	// inside the logger timestamp (data complete: kept).
	struct TCut
	{
		size_t keep;
		size_t scans;
	};
	const size_t tsAt = b.find("976052858");
	for (const TCut cut : {TCut{10, 1}, TCut{tsAt + 12, 1}, TCut{b.size() - 4, 2}})
	{
		const std::string path = writeLog(dir, "cut.clf", a + b.substr(0, cut.keep));
		const auto r = readWholeLog(path);
		ASSERT_FALSE(r.error);
		EXPECT_EQ(r.stats.scans, cut.scans) << cut.keep;
		if (cut.scans == 1)
		{
			ASSERT_EQ(r.warnings.size(), 1u) << cut.keep;
			EXPECT_TRUE(contains(r.warnings[0], path + ": line 2:")) << r.warnings[0];
			EXPECT_TRUE(contains(r.warnings[0], "truncated")) << r.warnings[0];
		}
	}
}
