/* Rawlog reader on real rawlogs (SENA, layout 1; simul, layout 1), on an observations-only
 * rawlog the test writes, and on broken copies: truncated, corrupted, reordered. */
#include <gtest/gtest.h>
#include <io_read_all.h>
#include <io_test_files.h>
#include <lrgc_apps/io/LogReader.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/serialization/CArchive.h>
#include <test_data.h>

#include <cmath>
#include <random>

using namespace lrgc::apps;
using lrgc::test::contains;
using lrgc::test::readWholeLog;
using mrpt::obs::CObservation2DRangeScan;
using mrpt::obs::CObservationOdometry;

namespace
{
const std::string kSimul =
	"/usr/share/mrpt/datasets/graphslam-engine-demos/action_observations_map/simul.rawlog";

// "<file>: byte N" -> N
uint64_t byteOf(const std::string& where)
{
	const size_t p = where.find(": byte ");
	return p == std::string::npos ? ~uint64_t(0) : std::stoull(where.substr(p + 7));
}

std::vector<uint64_t> entryOffsets(const lrgc::test::TReadResult& r)
{
	std::vector<uint64_t> out;
	for (const auto& e : r.entries) out.push_back(byteOf(e.where));
	return out;
}

mrpt::Clock::time_point t(double s)
{
	return mrpt::Clock::fromDouble(s);
}

CObservationOdometry::Ptr odometry(double time, double x)
{
	auto o = CObservationOdometry::Create();
	o->sensorLabel = "ODOMETRY";
	o->timestamp = t(time);
	o->odometry = mrpt::poses::CPose2D(x, 0, 0);
	return o;
}

CObservation2DRangeScan::Ptr scan(double time, const std::vector<float>& ranges)
{
	auto s = CObservation2DRangeScan::Create();
	s->sensorLabel = "LASER";
	s->timestamp = t(time);
	s->aperture = float(M_PI);
	s->maxRange = 30;
	s->resizeScan(ranges.size());
	for (size_t i = 0; i < ranges.size(); ++i)
	{
		s->setScanRange(i, ranges[i]);
		s->setScanRangeValidity(i, true);
	}
	return s;
}

// An observations-only rawlog with some problems: NaN/negative ranges, an empty scan, an
// object that is no observation, time going backwards.
void writeObservationsOnlyRawlog(const std::string& path)
{
	mrpt::io::CFileGZOutputStream f(path);
	auto out = mrpt::serialization::archiveFrom(f);
	out << *odometry(10.0, 0.0);
	out << *scan(10.0, {1, NAN, 2, -1, 3});
	out << *odometry(10.2, 0.1);
	out << *scan(10.2, {});
	out << mrpt::poses::CPose2D(1, 2, 3);
	out << *scan(9.9, {4, 5, 6});
	out << *odometry(10.3, 0.2);
}

// The SENA rawlog, uncompressed, in the test's directory.
std::string plainSenaCopy(const std::string& dir)
{
	const std::string path = dir + "/sena-plain.rawlog";
	lrgc::test::writeFileBytes(path,
							   lrgc::test::readUncompressed(lrgc::test::senaRawlogPath()));
	return path;
}
}  // namespace

TEST(RawlogReader, ReadsSenaLayout1)
{
	const std::string path = lrgc::test::senaRawlogPath();
	LRGC_SKIP_IF_MISSING(path);
	EXPECT_EQ(detectLogFormat(path), LogFormat::MrptRawlog);
	const auto r = readWholeLog(path);
	ASSERT_FALSE(r.error) << *r.error;
	EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
	// 224 action/frame pairs, plus the leading frame without actions that MRPT's own loop
	// (rawlog-edit, icp-slam) skips.
	ASSERT_EQ(r.entries.size(), 225u);
	EXPECT_EQ(r.stats.scans, 225u);
	EXPECT_EQ(r.stats.odometry, 224u);
	EXPECT_EQ(r.entries[0].where, path + ": byte 0");
	EXPECT_EQ(r.entries[0].actions->size(), 0u);
	for (size_t i = 0; i < r.entries.size(); ++i)
	{
		const TLogEntry& e = r.entries[i];
		ASSERT_TRUE(e.actions && e.observations) << i;
		EXPECT_FALSE(e.observation);
		if (i > 0)
		{
			ASSERT_EQ(e.actions->size(), 1u);
			EXPECT_TRUE(e.actions->getActionByClass<mrpt::obs::CActionRobotMovement2D>());
		}
		const auto s = e.observations->getObservationByClass<CObservation2DRangeScan>();
		ASSERT_TRUE(s) << i;
		EXPECT_EQ(s->getScanSize(), 361u);
	}
	EXPECT_NEAR(
		mrpt::Clock::toDouble(r.entries[1].observations->getObservationByIndex(0)->timestamp),
		1137834225.973760, 1e-6);
	EXPECT_DOUBLE_EQ(r.fractions.back(), 1.0);
}

TEST(RawlogReader, ReadsSimulLayout1EndingWithAnActionAlone)
{
	LRGC_SKIP_IF_MISSING(kSimul);
	const auto r = readWholeLog(kSimul);
	ASSERT_FALSE(r.error) << *r.error;
	EXPECT_EQ(r.stats.scans, 1733u);
	EXPECT_EQ(r.stats.odometry, 1732u);
	ASSERT_EQ(r.warnings.size(), 1u);
	EXPECT_TRUE(
		contains(r.warnings[0], kSimul + ": byte 3701519: the file ends with this action"))
		<< r.warnings[0];
}

TEST(RawlogReader, ReadsAnObservationsOnlyRawlogReportingItsProblems)
{
	const std::string dir = lrgc::test::makeTempDir("rawlog_layout2");
	const std::string path = dir + "/obs-only.rawlog";
	writeObservationsOnlyRawlog(path);
	const auto r = readWholeLog(path);
	ASSERT_FALSE(r.error) << *r.error;
	ASSERT_EQ(r.entries.size(), 5u);
	const double times[] = {10.0, 10.0, 10.2, 9.9, 10.3};
	for (size_t i = 0; i < 5; ++i)
	{
		ASSERT_TRUE(r.entries[i].observation);
		EXPECT_FALSE(r.entries[i].actions);
		EXPECT_NEAR(mrpt::Clock::toDouble(r.entries[i].observation->timestamp), times[i], 1e-6);
	}
	const auto s = std::dynamic_pointer_cast<CObservation2DRangeScan>(r.entries[1].observation);
	ASSERT_TRUE(s);
	const bool valid[] = {true, false, true, false, true};
	for (size_t i = 0; i < 5; ++i) EXPECT_EQ(s->getScanRangeValidity(i), valid[i]) << i;
	EXPECT_EQ(r.stats.scans, 2u);
	EXPECT_EQ(r.stats.odometry, 3u);
	EXPECT_EQ(r.stats.invalidRanges, 2u);
	EXPECT_EQ(r.stats.emptyScans, 1u);
	EXPECT_EQ(r.stats.ignoredObjects, 1u);
	EXPECT_EQ(r.stats.scanTimeJumpsBack, 1u);
	ASSERT_EQ(r.warnings.size(), 4u);
	for (const auto& w : r.warnings) EXPECT_TRUE(contains(w, path + ": byte ")) << w;
	EXPECT_TRUE(contains(r.warnings[0], "2 NaN, infinite or negative range(s) of 5"));
	EXPECT_TRUE(contains(r.warnings[1], "scan 'LASER' with 0 ray(s) skipped"));
	EXPECT_TRUE(contains(r.warnings[2], "CPose2D ignored"));
	EXPECT_TRUE(contains(r.warnings[3], "LASER timestamp 9.9"));
}

TEST(RawlogReader, GivesUncompressedByteOffsetsForPlainAndGzipAlike)
{
	LRGC_SKIP_IF_MISSING(lrgc::test::senaRawlogPath());
	const std::string dir = lrgc::test::makeTempDir("rawlog_plain");
	const auto gz = readWholeLog(lrgc::test::senaRawlogPath());
	const auto plain = readWholeLog(plainSenaCopy(dir));
	ASSERT_FALSE(plain.error);
	EXPECT_EQ(entryOffsets(plain), entryOffsets(gz));
	EXPECT_EQ(byteOf(gz.entries[1].where), 2049u);
}

TEST(RawlogReader, TruncatedCopiesFailAfterEveryCompleteEntryNamingTheByte)
{
	LRGC_SKIP_IF_MISSING(lrgc::test::senaRawlogPath());
	const std::string dir = lrgc::test::makeTempDir("rawlog_truncated");
	const std::string plainPath = plainSenaCopy(dir);
	const auto whole = readWholeLog(plainPath);
	const std::vector<uint64_t> at = entryOffsets(whole);
	const std::string bytes = lrgc::test::readFileBytes(plainPath);

	struct TCut
	{
		uint64_t keep;
		size_t entries;
		uint64_t placeFrom, placeTo;  // the error's byte is in [from, to)
	};
	const TCut cuts[] = {
		{5, 0, 0, 1},                               // inside the first class name
		{at[100] + 50, 100, at[100], at[100] + 1},  // inside entry 100's action collection
		{at[101] - 50, 100, at[100] + 1, at[101]},  // inside entry 100's sensory frame
		{bytes.size() - 1, 224, at[224] + 1, bytes.size()}};
	for (const TCut& c : cuts)
	{
		const std::string path = dir + "/cut" + std::to_string(c.keep) + ".rawlog";
		lrgc::test::writeFileBytes(path, bytes.substr(0, c.keep));
		const auto r = readWholeLog(path);
		ASSERT_TRUE(r.error) << "cut at " << c.keep;
		EXPECT_TRUE(contains(*r.error, path + ": byte ")) << *r.error;
		EXPECT_TRUE(contains(*r.error, "truncated")) << *r.error;
		const uint64_t place = byteOf(*r.error);
		EXPECT_GE(place, c.placeFrom) << *r.error;
		EXPECT_LT(place, c.placeTo) << *r.error;
		ASSERT_EQ(r.entries.size(), c.entries) << c.keep;
		for (size_t i = 0; i < r.entries.size(); ++i)
			EXPECT_EQ(r.entries[i].where, path + ": byte " + std::to_string(at[i]));
	}
	// A plain rawlog cut between two objects is indistinguishable from a shorter log.
	const std::string between = dir + "/cut-between.rawlog";
	lrgc::test::writeFileBytes(between, bytes.substr(0, at[100]));
	const auto r = readWholeLog(between);
	EXPECT_FALSE(r.error);
	EXPECT_EQ(r.entries.size(), 100u);
}

TEST(RawlogReader, TruncatedGzipCopiesAlwaysFail)
{
	LRGC_SKIP_IF_MISSING(lrgc::test::senaRawlogPath());
	const std::string dir = lrgc::test::makeTempDir("rawlog_gz_truncated");
	const auto whole = readWholeLog(lrgc::test::senaRawlogPath());
	const std::string bytes = lrgc::test::readFileBytes(lrgc::test::senaRawlogPath());
	for (const size_t keep :
		 {size_t(100), bytes.size() / 3, bytes.size() / 2, bytes.size() - 8, bytes.size() - 1})
	{
		const std::string path = dir + "/cut" + std::to_string(keep) + ".rawlog";
		lrgc::test::writeFileBytes(path, bytes.substr(0, keep));
		const auto r = readWholeLog(path);
		ASSERT_TRUE(r.error) << "cut at " << keep << " went unnoticed";
		EXPECT_TRUE(contains(*r.error, path + ": byte ")) << *r.error;
		ASSERT_LE(r.entries.size(), whole.entries.size());
		for (size_t i = 0; i < r.entries.size(); ++i)
			EXPECT_EQ(byteOf(r.entries[i].where), byteOf(whole.entries[i].where));
		if (keep >= bytes.size() - 8)
		{
			EXPECT_EQ(r.entries.size(), whole.entries.size());
		}
	}
}

TEST(RawlogReader, CorruptObjectsFailNamingTheirByte)
{
	LRGC_SKIP_IF_MISSING(lrgc::test::senaRawlogPath());
	const std::string dir = lrgc::test::makeTempDir("rawlog_corrupt");
	const std::string plainPath = plainSenaCopy(dir);
	const std::vector<uint64_t> at = entryOffsets(readWholeLog(plainPath));
	const std::string bytes = lrgc::test::readFileBytes(plainPath);
	struct TDamage
	{
		uint64_t offset;
		char value;
		size_t entries;  // complete entries before the damage
		uint64_t place;  // the byte the error names
	};
	const TDamage damages[] = {
		// Header byte of entry 50's action collection: a 5-letter class name.
		{at[50], char(0x85), 50, at[50]},
		// A letter of the class name of entry 60's action collection.
		{at[60] + 4, 'X', 60, at[60]},
		// One byte inside entry 202's odometry increment: MRPT's deserializer segfaults on
		// it (found by fuzzing; the guard process meets it first).
		{447917, char(40), 202, 447867}};
	for (const TDamage& d : damages)
	{
		std::string b = bytes;
		b[d.offset] = d.value;
		const std::string path = dir + "/corrupt" + std::to_string(d.offset) + ".rawlog";
		lrgc::test::writeFileBytes(path, b);
		const auto r = readWholeLog(path);
		ASSERT_TRUE(r.error) << d.offset;
		EXPECT_TRUE(
			contains(*r.error, path + ": byte " + std::to_string(d.place) + ": corrupt object"))
			<< *r.error;
		EXPECT_EQ(r.entries.size(), d.entries) << *r.error;
	}
}

TEST(RawlogReader, RandomlyCorruptedCopiesNeverCrashTheReader)
{
	LRGC_SKIP_IF_MISSING(lrgc::test::senaRawlogPath());
	const std::string dir = lrgc::test::makeTempDir("rawlog_fuzz");
	const std::string gzBytes = lrgc::test::readFileBytes(lrgc::test::senaRawlogPath());
	const std::string plainBytes = lrgc::test::readFileBytes(plainSenaCopy(dir));
	std::mt19937 rng(20240611);
	for (const bool gz : {false, true})
	{
		const std::string& orig = gz ? gzBytes : plainBytes;
		size_t errors = 0;
		for (int trial = 0; trial < 15; ++trial)
		{
			std::string b = orig;
			for (int k = 0, n = 1 + int(rng() % 3); k < n; ++k)
				b[rng() % b.size()] ^= char(1 + rng() % 255);
			const std::string path = dir + "/fuzz.rawlog";
			lrgc::test::writeFileBytes(path, b);
			// Either a complete read (plain rawlogs carry no checksum) or CLogReadError
			// naming the file; any other exception or a crash fails the test.
			const auto r = readWholeLog(path);
			if (r.error)
			{
				++errors;
				EXPECT_TRUE(contains(*r.error, path + ": ")) << *r.error;
			}
		}
		// gzip's CRC-32 catches every corruption; a plain file only some.
		if (gz)
			EXPECT_EQ(errors, 15u);
		else
			EXPECT_GT(errors, 0u);
	}
}

TEST(RawlogReader, ReturnsReorderedObjectsInFileOrder)
{
	const std::string dir = lrgc::test::makeTempDir("rawlog_reordered");
	const std::string path = dir + "/ordered.rawlog";
	{
		mrpt::io::CFileOutputStream f(path);  // plain, so objects can be cut out
		auto out = mrpt::serialization::archiveFrom(f);
		for (int k = 0; k < 4; ++k) out << *scan(1.0 + k, {1.f + k, 2, 3});
	}
	const auto r0 = readWholeLog(path);
	ASSERT_EQ(r0.entries.size(), 4u);
	const std::vector<uint64_t> at = entryOffsets(r0);
	const std::string b = lrgc::test::readFileBytes(path);
	const auto piece = [&](size_t k)
	{ return b.substr(at[k], (k + 1 < at.size() ? at[k + 1] : b.size()) - at[k]); };
	const std::string swapped = dir + "/swapped.rawlog";
	lrgc::test::writeFileBytes(swapped, piece(0) + piece(2) + piece(1) + piece(3));
	const auto r = readWholeLog(swapped);
	ASSERT_FALSE(r.error);
	ASSERT_EQ(r.entries.size(), 4u);
	const double expected[] = {1.0, 3.0, 2.0, 4.0};
	for (size_t i = 0; i < 4; ++i)
		EXPECT_NEAR(mrpt::Clock::toDouble(r.entries[i].observation->timestamp), expected[i],
					1e-6);
	EXPECT_EQ(r.stats.scanTimeJumpsBack, 1u);
	ASSERT_EQ(r.warnings.size(), 1u);
	EXPECT_TRUE(contains(r.warnings[0], swapped + ": byte " + std::to_string(at[2])));
}

TEST(RawlogReader, AnActionCollectionClaimingBillionsOfActionsIsACorruptObject)
{
	// Found by fuzz/fuzz_rawlog: a CActionCollection whose action count reads 4098424833
	// makes MRPT's deserializer grow a deque to many GiB. The guard process meets it first,
	// under its memory limit, and the reader names the object instead of taking the memory.
	const std::string dir = lrgc::test::makeTempDir("rawlog_huge_count");
	mrpt::obs::CActionRobotMovement2D move;
	move.computeFromOdometry(mrpt::poses::CPose2D(0.1, 0, 0),
							 mrpt::obs::CActionRobotMovement2D::TMotionModelOptions());
	mrpt::obs::CActionCollection actions;
	actions.insert(move);
	const std::string path = dir + "/huge-count.rawlog";
	{
		mrpt::io::CFileOutputStream f(path);
		auto out = mrpt::serialization::archiveFrom(f);
		out << actions;
	}
	std::string bytes = lrgc::test::readFileBytes(path);
	// Object header: 1 byte (0x80 | name length), the class name, the version (1 byte), then
	// the uint32 count of actions.
	const std::string name = "mrpt::obs::CActionCollection";
	ASSERT_EQ(bytes.substr(1, name.size()), name);
	const size_t countAt = 1 + name.size() + 1;
	ASSERT_EQ(bytes.substr(countAt, 4), std::string("\x01\x00\x00\x00", 4));
	bytes.replace(countAt, 4, std::string("\x01\x00\x49\xf4", 4));
	lrgc::test::writeFileBytes(path, bytes);
	const auto r = lrgc::test::readWholeLog(path);
	ASSERT_TRUE(r.error);
	EXPECT_TRUE(contains(*r.error, path + ": byte 0: corrupt object")) << *r.error;
	EXPECT_TRUE(r.entries.empty());
}
