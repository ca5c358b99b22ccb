/* CLaserSelector: the laser to map (first seen, or the one asked for), the warning about a
 * second laser, per-label counts, and range limits (applyRangeLimits) on the robot's posts. */
#include <gtest/gtest.h>

#include <lrgc/map_builder/LaserSelector.h>

namespace
{
using mrpt::obs::CObservation2DRangeScan;

/** A 181-beam, 180-degree scan of `label`: every reading `range` [m], valid. */
CObservation2DRangeScan::Ptr scan(const std::string& label, float range = 3.0f)
{
	auto s = CObservation2DRangeScan::Create();
	s->sensorLabel = label;
	s->aperture = static_cast<float>(M_PI);
	s->maxRange = 30;
	s->resizeScan(181);
	for (size_t i = 0; i < 181; ++i)
		s->setScanRange(i, range), s->setScanRangeValidity(i, true);
	return s;
}
}  // namespace

TEST(LaserSelector, FirstSeenIsMappedAndASecondLaserIsWarnedAboutOnce)
{
	lrgc::CLaserSelector sel;
	EXPECT_EQ(sel.label(), "");
	EXPECT_TRUE(sel.select(scan("REAR_LASER")));
	EXPECT_FALSE(sel.takeWarning());
	EXPECT_FALSE(sel.select(scan("LASER")));
	const auto w = sel.takeWarning();
	ASSERT_TRUE(w);
	for (const char* word : {"'REAR_LASER'", "'LASER'", "--laser LASER", "laser_label"})
		EXPECT_NE(w->find(word), std::string::npos) << word << " not in: " << *w;
	EXPECT_FALSE(sel.select(scan("LASER")));
	EXPECT_FALSE(sel.select(scan("THIRD")));
	EXPECT_FALSE(sel.takeWarning()) << "warned more than once";
	EXPECT_TRUE(sel.select(scan("REAR_LASER")));
	EXPECT_EQ(sel.label(), "REAR_LASER");
	EXPECT_FALSE(sel.chosen());
	const std::map<std::string, size_t> expected{{"LASER", 2}, {"THIRD", 1}};
	EXPECT_EQ(sel.ignoredScans(), expected);
}

TEST(LaserSelector, TheChosenLaserIsMappedFromTheStartWithoutWarning)
{
	lrgc::TMapBuilderParams p;
	p.laser_label = "LASER";
	lrgc::CLaserSelector sel(p);
	EXPECT_FALSE(sel.select(scan("REAR_LASER")));
	EXPECT_TRUE(sel.select(scan("LASER")));
	EXPECT_FALSE(sel.takeWarning());
	EXPECT_TRUE(sel.chosen());
	EXPECT_EQ(sel.label(), "LASER");
	EXPECT_EQ(sel.ignoredScans().at("REAR_LASER"), 1u);
	sel.adopt("OTHER");  // a map given to initialize() does not override the choice
	EXPECT_EQ(sel.label(), "LASER");
}

TEST(LaserSelector, WithoutRangeLimitsTheScanPassesUntouched)
{
	lrgc::CLaserSelector sel;
	const auto in = scan("LASER", 0.1f);
	EXPECT_EQ(sel.select(in), in);  // the same object: no copy on the default path
	EXPECT_EQ(sel.rangeLimitedReadings(), 0u);
}

TEST(RangeLimits, PostsAndFarReadingsAreMarkedInvalidOnACopy)
{
	auto in = scan("LASER", 4.0f);
	for (size_t i : {10, 11, 12, 170}) in->setScanRange(i, 0.12f);  // the robot's posts
	in->setScanRange(90, 25.0f);
	in->setScanRange(91, 0.05f), in->setScanRangeValidity(91, false);  // already invalid
	size_t marked = 0;
	const auto out = lrgc::applyRangeLimits(in, {0.3, 20.0}, &marked);
	ASSERT_NE(out, in);
	EXPECT_EQ(marked, 5u);
	for (size_t i : {10, 11, 12, 170, 90}) EXPECT_FALSE(out->getScanRangeValidity(i)) << i;
	for (size_t i : {0, 9, 13, 89, 180}) EXPECT_TRUE(out->getScanRangeValidity(i)) << i;
	EXPECT_FLOAT_EQ(out->getScanRange(10), 0.12f);  // ranges kept, only flagged
	EXPECT_TRUE(in->getScanRangeValidity(10));      // the input is never changed
	// Exactly at a limit is inside; max_range_m 0 is no upper limit.
	EXPECT_EQ(
		lrgc::applyRangeLimits(scan("LASER", 0.3f), {0.3, 0}, &marked)->getScanRangeValidity(0),
		true);
	EXPECT_EQ(marked, 0u);
	const auto far = lrgc::applyRangeLimits(scan("LASER", 29.0f), {0.0, 0.0}, &marked);
	EXPECT_EQ(marked, 0u);
	EXPECT_TRUE(far->getScanRangeValidity(0));
	// The scan conversion then drops them like any invalid reading.
	lrgc::TScanConversionStats st;
	const auto pts = lrgc::scanFromObservation(*out, &st);
	EXPECT_EQ(pts.points.size(), 181u - 6u);
	EXPECT_EQ(st.invalidFlag, 6u);
}
