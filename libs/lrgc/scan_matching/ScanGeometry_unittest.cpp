/* checkScanGeometry: the scans of issue 30 (NaN aperture or sensor pose, an aperture from an
 * angular resolution of 1e300, maxRange 0, readings of 1e20 and 1e25 m) are dropped or
 * clipped, with a reason; a valid scan passes untouched (the same object). */
#include <gtest/gtest.h>
#include <lrgc/scan_matching/ScanGeometry.h>

#include <cmath>
#include <limits>

using namespace lrgc;

namespace
{
mrpt::obs::CObservation2DRangeScan::Ptr validScan()
{
	auto s = mrpt::obs::CObservation2DRangeScan::Create();
	s->aperture = static_cast<float>(M_PI);
	s->maxRange = 80.0f;
	s->sensorPose = mrpt::poses::CPose3D(0.1, 0, 0.3, 0, 0, 0);
	s->resizeScan(181);
	for (size_t i = 0; i < 181; ++i) s->setScanRange(i, 2.0f), s->setScanRangeValidity(i, true);
	return s;
}
const double kNaN = std::numeric_limits<double>::quiet_NaN();
}  // namespace

TEST(ScanGeometry, ValidScanPassesUntouched)
{
	const auto s = validScan();
	const auto c = checkScanGeometry(s);
	EXPECT_EQ(c.scan, s);
	EXPECT_TRUE(c.problem.empty());
	EXPECT_EQ(c.clipped, 0u);
}

TEST(ScanGeometry, UnusableGeometryDropsTheScanNamingWhy)
{
	const auto dropped = [](auto&& spoil, const std::string& named)
	{
		auto s = validScan();
		spoil(*s);
		const auto c = checkScanGeometry(s);
		EXPECT_FALSE(c.scan) << named;
		EXPECT_NE(c.problem.find(named), std::string::npos) << c.problem;
	};
	dropped([](auto& s) { s.aperture = static_cast<float>(kNaN); }, "aperture");
	dropped([](auto& s) { s.aperture = std::numeric_limits<float>::infinity(); },
			"aperture");  // 1e300 x 180
	dropped([](auto& s) { s.aperture = 7.0f; }, "aperture");
	dropped([](auto& s) { s.aperture = 0.0f; }, "aperture");
	dropped([](auto& s) { s.sensorPose.x(kNaN); }, "sensorPose");
	dropped([](auto& s) { s.sensorPose.setYawPitchRoll(kNaN, 0, 0); }, "sensorPose");
	dropped([](auto& s) { s.sensorPose.y(1e6); }, "sensorPose");
	dropped([](auto& s) { s.maxRange = 0.0f; }, "maxRange = 0");
	dropped([](auto& s) { s.maxRange = static_cast<float>(kNaN); }, "maxRange");
	dropped([](auto& s) { s.resizeScan(0); }, "0 ray(s): fewer than 2");
	dropped([](auto& s) { s.resizeScan(1); }, "1 ray(s): fewer than 2");  // found by fuzz_scan
}

TEST(ScanGeometry, FarReadingsAreClippedAndCounted)
{
	auto s = validScan();
	s->maxRange = 1e30f;  // a ROBOTLASER1 line's maximum_range
	s->setScanRange(3, 1e25f);
	s->setScanRange(7, 1e20f);
	s->setScanRange(9, 999.0f);  // far, but a reading some lidars make
	const auto c = checkScanGeometry(s);
	ASSERT_TRUE(c.scan);
	EXPECT_EQ(c.clipped, 2u);
	EXPECT_FALSE(c.scan->getScanRangeValidity(3));
	EXPECT_FALSE(c.scan->getScanRangeValidity(7));
	EXPECT_TRUE(c.scan->getScanRangeValidity(9));
	EXPECT_LE(c.scan->maxRange, kMaxRange);
	EXPECT_TRUE(s->getScanRangeValidity(3)) << "the observation itself was changed";
}
