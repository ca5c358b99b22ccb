/* The CARMEN reader on the shared benchmark logs (skipped where they are absent): scan and
 * odometry counts as in /work/shared/datasets/README.md, beams, no obstacle at max range,
 * file order (Intel's 631 backward jumps kept), and every relation timestamp found among
 * the scan timestamps. Expected counts of no-return sentinels were taken independently with
 * zcat | awk over the readings (81.83 Intel, 50 ACES, 81.91 MIT-CSAIL). Also broken copies
 * of MIT-CSAIL: lines swapped, a line corrupted, the text cut, the gzip stream cut. */
#include <gtest/gtest.h>
#include <io_read_all.h>
#include <io_test_files.h>
#include <lrgc_apps/io/LogReader.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <test_data.h>

#include <algorithm>
#include <fstream>
#include <sstream>

using namespace lrgc::apps;
using mrpt::obs::CObservation2DRangeScan;
using mrpt::obs::CObservationOdometry;

namespace
{
struct TDataset
{
	const char* name;
	size_t scans, odomLines, beams, noReturns, scanJumpsBack;
	float largestRealReading;  // [m], zcat | awk: the largest reading below the sentinel
};

// gtest prints the parameter in test names: the dataset's name, not its bytes.
void PrintTo(const TDataset& d, std::ostream* os)
{
	*os << d.name;
}

class CarmenDatasets : public ::testing::TestWithParam<TDataset>
{
};

std::vector<double> relationTimes(const std::string& path)
{
	std::vector<double> times;
	std::ifstream f(path);
	std::string line;
	while (std::getline(f, line))
	{
		std::istringstream s(line);
		double t1, t2;
		if (s >> t1 >> t2) times.insert(times.end(), {t1, t2});
	}
	return times;
}
}  // namespace

TEST_P(CarmenDatasets, ReadsTheBenchmarkLogAsTheReadmeDescribes)
{
	const TDataset& d = GetParam();
	const std::string log =
		lrgc::test::sharedDatasetPath(std::string(d.name) + "/" + d.name + ".clf.gz");
	const std::string rel =
		lrgc::test::sharedDatasetPath(std::string(d.name) + "/" + d.name + ".relations");
	LRGC_SKIP_IF_MISSING(log);
	ASSERT_EQ(detectLogFormat(log), LogFormat::Carmen);

	const auto reader = openLog(log);
	std::vector<double> scanTimes;
	size_t scans = 0, odometry = 0, validReadings = 0;
	float largestValid = 0;
	mrpt::obs::CObservation::Ptr previous;
	while (const auto e = reader->next())
	{
		ASSERT_TRUE(e->observation);
		if (const auto s = std::dynamic_pointer_cast<CObservation2DRangeScan>(e->observation))
		{
			++scans;
			ASSERT_EQ(s->getScanSize(), d.beams);
			ASSERT_EQ(s->sensorLabel, "LASER");
			// Its odometry, from the same line, comes right before it, with its timestamp.
			const auto odo = std::dynamic_pointer_cast<CObservationOdometry>(previous);
			ASSERT_TRUE(odo) << e->where;
			ASSERT_EQ(odo->timestamp, s->timestamp) << e->where;
			for (size_t i = 0; i < s->getScanSize(); ++i)
			{
				if (!s->getScanRangeValidity(i)) continue;
				++validReadings;
				largestValid = std::max(largestValid, s->getScanRange(i));
				ASSERT_LT(s->getScanRange(i), s->maxRange) << e->where << " beam " << i;
			}
			scanTimes.push_back(mrpt::Clock::toDouble(s->timestamp));
		}
		else
			++odometry;
		previous = e->observation;
	}
	const TLogReadStats& st = reader->stats();
	EXPECT_EQ(scans, d.scans);
	EXPECT_EQ(st.scans, d.scans);
	EXPECT_EQ(odometry, d.scans + d.odomLines);
	EXPECT_EQ(st.skippedLines, 0u);
	EXPECT_EQ(st.invalidRanges, 0u);
	EXPECT_EQ(st.noReturnRanges, d.noReturns);
	EXPECT_EQ(validReadings, d.scans * d.beams - d.noReturns);
	EXPECT_FLOAT_EQ(largestValid, d.largestRealReading);
	EXPECT_EQ(st.scanTimeJumpsBack, d.scanJumpsBack);
	EXPECT_DOUBLE_EQ(reader->fractionRead(), 1.0);

	// Every relation's t1 and t2 is a scan timestamp (to 1e-5 s).
	if (!lrgc::test::fileExists(rel)) return;
	std::sort(scanTimes.begin(), scanTimes.end());  // a lookup table; the log stays in order
	const std::vector<double> times = relationTimes(rel);
	ASSERT_FALSE(times.empty());
	size_t missing = 0;
	for (const double t : times)
	{
		const auto it = std::lower_bound(scanTimes.begin(), scanTimes.end(), t - 1e-5);
		if (it == scanTimes.end() || *it > t + 1e-5) ++missing;
	}
	EXPECT_EQ(missing, 0u) << "of " << times.size() << " relation timestamps";
}

INSTANTIATE_TEST_SUITE_P(
	SharedLogs, CarmenDatasets,
	::testing::Values(TDataset{"intel", 13631, 26915, 180, 68313, 631, 26.37f},
					  TDataset{"aces", 7374, 7375, 180, 11139, 0, 49.91f},
					  TDataset{"mit-csail", 1988, 0, 361, 23711, 0, 42.40f}),
	[](const ::testing::TestParamInfo<TDataset>& param)
	{
		std::string n = param.param.name;
		std::replace(n.begin(), n.end(), '-', '_');
		return n;
	});

TEST(CarmenDatasetCopies, ReadsABrokenCopyOfMitCsailSayingWhatItSkipped)
{
	const std::string mit = lrgc::test::sharedDatasetPath("mit-csail/mit-csail.clf.gz");
	LRGC_SKIP_IF_MISSING(mit);
	const std::string dir = lrgc::test::makeTempDir("carmen_mit_broken");
	std::vector<std::string> lines;
	{
		const std::string text = lrgc::test::readUncompressed(mit);
		size_t pos = 0;
		for (size_t nl; (nl = text.find('\n', pos)) != std::string::npos; pos = nl + 1)
			lines.push_back(text.substr(pos, nl + 1 - pos));
	}
	ASSERT_EQ(lines.size(), 1991u);                          // 3 comment lines, 1988 FLASER
	std::swap(lines[100], lines[101]);                       // lines 101 and 102 reordered
	lines[200].replace(lines[200].find(' ', 11), 1, " x ");  // line 201: a bad reading
	std::string broken;
	for (const auto& l : lines) broken += l;
	broken.resize(broken.size() - 40);                    // cut inside the last line's poses
	const std::string path = dir + "/mit-broken.rawlog";  // a misleading name, too
	lrgc::test::writeGzFile(path, broken);

	const auto r = lrgc::test::readWholeLog(path);
	ASSERT_FALSE(r.error) << *r.error;
	EXPECT_EQ(r.stats.scans, 1988u - 2u);
	EXPECT_EQ(r.stats.skippedLines, 2u);
	EXPECT_EQ(r.stats.scanTimeJumpsBack, 1u);
	ASSERT_EQ(r.warnings.size(), 3u);
	EXPECT_TRUE(lrgc::test::contains(r.warnings[0], path + ": line 102: FLASER timestamp"));
	EXPECT_TRUE(lrgc::test::contains(r.warnings[1], path + ": line 201: malformed FLASER"));
	EXPECT_TRUE(lrgc::test::contains(r.warnings[2], path + ": line 1991: malformed FLASER"));
	EXPECT_TRUE(lrgc::test::contains(r.warnings[2], "the file may be truncated"));

	// The original gzip file cut in the middle: every complete line, then the error.
	const std::string bytes = lrgc::test::readFileBytes(mit);
	const std::string cut = dir + "/mit-cut.clf.gz";
	lrgc::test::writeFileBytes(cut, bytes.substr(0, bytes.size() / 2));
	const auto c = lrgc::test::readWholeLog(cut);
	ASSERT_TRUE(c.error);
	EXPECT_TRUE(lrgc::test::contains(*c.error, cut + ": byte ")) << *c.error;
	EXPECT_GT(c.stats.scans, 900u);
	EXPECT_LT(c.stats.scans, 1100u);
}
