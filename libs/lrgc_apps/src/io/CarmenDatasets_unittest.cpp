/* The CARMEN reader on the shared benchmark logs (skipped where they are absent): scan and
 * odometry counts as in /work/shared/datasets/README.md, beams, no obstacle at max range,
 * file order (Intel's 631 backward jumps kept), and every relation timestamp found among
 * the scan timestamps. Expected counts of no-return sentinels were taken independently with
 * zcat | awk over the readings (81.83 Intel, 50 ACES, 81.91 MIT-CSAIL). */
#include <gtest/gtest.h>
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
