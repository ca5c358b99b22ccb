#include <gtest/gtest.h>
#include <lrgc_apps/io/LogReader.h>
#include "live/CaptureWriter.h"
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <filesystem>

#include "app_runner.h"
#include "test_data.h"

using namespace lrgc::apps;

namespace
{
mrpt::obs::CObservation2DRangeScan::Ptr scan(int k)
{
	auto s = mrpt::obs::CObservation2DRangeScan::Create();
	s->sensorLabel = "LASER";
	s->timestamp = mrpt::Clock::fromDouble(1000.0 + k);
	s->resizeScan(50);
	for (size_t i = 0; i < 50; ++i)
	{
		s->setScanRange(i, 1.0f + 0.01f * k + 0.001f * i);
		s->setScanRangeValidity(i, true);
	}
	return s;
}

size_t entries(const std::string& path)
{
	auto reader = openLog(path);
	size_t n = 0;
	while (reader->next()) ++n;  // throws on a partial object
	return n;
}
}  // namespace

TEST(CaptureWriter, FileHoldsWholeObjectsAfterEveryAppend)
{
	const std::string path = lrgc::test::makeTempDir("capture_whole") + "/capture.rawlog";
	CCaptureWriter w(path);
	for (int k = 0; k < 4; ++k)
	{
		w.append(*scan(k));
		EXPECT_EQ(entries(path), static_cast<size_t>(k + 1)) << "readable while being written";
		EXPECT_EQ(std::filesystem::file_size(path), w.bytes());
	}
	w.close();
	auto reader = openLog(path);
	for (int k = 0; k < 4; ++k)
	{
		const auto e = reader->next();
		ASSERT_TRUE(e && e->observation);
		const auto s =
			std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(e->observation);
		ASSERT_TRUE(s);
		EXPECT_FLOAT_EQ(s->getScanRange(7), 1.0f + 0.01f * k + 0.007f);
		EXPECT_EQ(s->timestamp, mrpt::Clock::fromDouble(1000.0 + k));
	}
	EXPECT_FALSE(reader->next());
	EXPECT_EQ(w.objects(), 4u);
	EXPECT_ANY_THROW(w.append(*scan(9)));  // closed
}

TEST(CaptureWriter, NeverOverwritesAFile)
{
	const std::string path = lrgc::test::makeTempDir("capture_exists") + "/capture.rawlog";
	lrgc::test::writeTextFile(path, "keep me");
	EXPECT_ANY_THROW(CCaptureWriter{path});
	EXPECT_EQ(lrgc::test::readTextFile(path), "keep me");
}
