#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <lrgc/map_builder/MapBuilderParams.h>

namespace
{
std::string saved(const lrgc::TLRGCParams& p)
{
	mrpt::config::CConfigFileMemory mem;
	p.saveToConfigFile(mem, {});
	return mem.getContent();
}
}  // namespace

TEST(LRGCParams, TextRoundTripIsExact)
{
	lrgc::TLRGCParams p;
	p.builder.keyframe_distance_m = 0.42;
	p.builder.keyframe_angle = mrpt::DEG2RAD(7.5);
	p.local.window_size = 13;
	p.motion.cv_sigma_phi = mrpt::DEG2RAD(12.0);
	const std::string text = saved(p);
	mrpt::config::CConfigFileMemory mem(text);
	lrgc::TLRGCParams q;
	q.loadFromConfigFile(mem, {});
	EXPECT_EQ(saved(q), text);
	EXPECT_NEAR(q.builder.keyframe_angle, mrpt::DEG2RAD(7.5), 1e-12);  // _deg keys load degrees
	EXPECT_EQ(q.local.window_size, 13u);
}

// Save writes every number exactly, in every section: MRPT's "%f" / "%e" wrote 0.00012345 as
// 0.000123 and relative_cost_tolerance = 1.000001e-04 as 1.000001e-04 whose next save differed.
TEST(LRGCParams, SaveWritesEveryNumberExactly)
{
	lrgc::TLRGCParams p;
	p.builder.keyframe_distance_m = 0.00012345;  // [MapBuilder], once padded
	p.optimizer.relative_cost_tolerance = 1.000001e-04;  // [PoseGraphOptimizer]
	p.correlator.blur_sigma_m = 0.1 + 1e-15;  // [PatchCorrelator], once unpadded
	p.matcher.normal_radius_m = 0.123456789012345;  // [ScanMatcher], once "%.10g"
	p.loop.max_window_phi = mrpt::DEG2RAD(17.123456789);  // a _deg key: through degrees
	p.revisits.max_phi = mrpt::DEG2RAD(44.999999999);
	const std::string text = saved(p);
	lrgc::TLRGCParams q;
	q.loadFromConfigFile(mrpt::config::CConfigFileMemory(text), {});
	EXPECT_EQ(q.builder.keyframe_distance_m, p.builder.keyframe_distance_m);
	EXPECT_EQ(q.optimizer.relative_cost_tolerance, p.optimizer.relative_cost_tolerance);
	EXPECT_EQ(q.correlator.blur_sigma_m, p.correlator.blur_sigma_m);
	EXPECT_EQ(q.matcher.normal_radius_m, p.matcher.normal_radius_m);
	EXPECT_EQ(q.loop.max_window_phi, p.loop.max_window_phi);
	EXPECT_EQ(q.revisits.max_phi, p.revisits.max_phi);
	EXPECT_EQ(saved(q), text);
	// The shortest text that reads back: defaults stay short ("0.3", not 0.29999999999999999).
	const std::string defaults = saved(lrgc::TLRGCParams());
	EXPECT_NE(defaults.find(" 0.3 "), std::string::npos) << defaults;
	EXPECT_NE(defaults.find(" 150 "), std::string::npos) << defaults;  // not 1.5e+02
	EXPECT_NE(text.find("0.00012345 "), std::string::npos) << text;
}

TEST(LRGCParams, EverySectionRejectsAnUnknownKey)
{
	for (const auto& section : lrgc::TLRGCParams::sectionNames())
	{
		mrpt::config::CConfigFileMemory mem("[" + section + "]\nno_such_key = 1\n");
		lrgc::TLRGCParams p;
		EXPECT_THROW(p.loadFromConfigFile(mem, {}), std::exception) << section;
	}
}

TEST(LRGCParams, InvalidValuesAreRejectedNamingTheKey)
{
	mrpt::config::CConfigFileMemory mem("[MapBuilder]\nkeyframe_distance_m = -1\n");
	lrgc::TLRGCParams p;
	try
	{
		p.loadFromConfigFile(mem, {});
		FAIL() << "negative keyframe_distance_m accepted";
	}
	catch (const std::exception& e)
	{
		EXPECT_NE(std::string(e.what()).find("keyframe_distance_m"), std::string::npos) << e.what();
	}
}

TEST(LRGCParams, UnknownSectionIsRejected)
{
	mrpt::config::CConfigFileMemory mem("[MapBuilderr]\nkeyframe_distance_m = 1\n");
	EXPECT_THROW(lrgc::rejectUnknownSections(mem, lrgc::TLRGCParams::sectionNames()), std::exception);
	mrpt::config::CConfigFileMemory ok("[MapBuilder]\nkeyframe_distance_m = 1\n");
	EXPECT_NO_THROW(lrgc::rejectUnknownSections(ok, lrgc::TLRGCParams::sectionNames()));
}

namespace
{
// The message of loading `text` into default parameters, or "" if it loads.
std::string loadError(const std::string& text)
{
	mrpt::config::CConfigFileMemory mem(text);
	lrgc::TLRGCParams p;
	try
	{
		p.loadFromConfigFile(mem, {});
	}
	catch (const std::exception& e)
	{
		return e.what();
	}
	return {};
}
}  // namespace

TEST(LRGCParams, ABadValueIsBlamedOnItsOwnKey)
{
	// Read leniently, 2.5 became 2 and the error blamed max_pairwise_links (default 5).
	const std::string fraction = loadError("[LocalRegistration]\nwindow_size = 2.5\n");
	EXPECT_NE(fraction.find("[LocalRegistration] window_size: '2.5' is not a whole number"),
			  std::string::npos)
		<< fraction;
	EXPECT_EQ(fraction.find("max_pairwise_links"), std::string::npos) << fraction;
	// A whole but too small window: the key that no longer fits says why, with both values.
	const std::string small = loadError("[LocalRegistration]\nwindow_size = 2\n");
	EXPECT_NE(
		small.find("max_pairwise_links: 5 must be below window_size (2) and "
				   "laser_only_window_size (10)"),
		std::string::npos)
		<< small;
	// Read leniently, "abc" was 0 and blamed as "must be > 0".
	const std::string text = loadError("[MapBuilder]\nkeyframe_distance_m = abc\n");
	EXPECT_NE(text.find("[MapBuilder] keyframe_distance_m: 'abc' is not a number"),
			  std::string::npos)
		<< text;
	EXPECT_EQ(
		loadError("[MapBuilder]\nloop_closing = No\n[LocalRegistration]\nwindow_size = 9\n"),
		"");
}

TEST(LRGCParams, LaserLabelAndRangeLimitsRoundTrip)
{
	lrgc::TLRGCParams p;
	EXPECT_EQ(p.builder.laser_label, "");
	EXPECT_EQ(p.builder.min_range_m, 0.0);
	EXPECT_EQ(p.builder.max_range_m, 0.0);
	p.builder.laser_label = "REAR_LASER";
	p.builder.min_range_m = 0.25;
	p.builder.max_range_m = 20;
	const std::string text = saved(p);
	mrpt::config::CConfigFileMemory mem(text);
	lrgc::TLRGCParams q;
	q.loadFromConfigFile(mem, {});
	EXPECT_EQ(q.builder.laser_label, "REAR_LASER");
	EXPECT_EQ(q.builder.min_range_m, 0.25);
	EXPECT_EQ(q.builder.max_range_m, 20.0);
	EXPECT_EQ(saved(q), text);
	// The default (empty label) survives the round trip too.
	mrpt::config::CConfigFileMemory defaults(saved(lrgc::TLRGCParams()));
	lrgc::TLRGCParams d;
	d.builder.laser_label = "X";
	d.loadFromConfigFile(defaults, {});
	EXPECT_EQ(d.builder.laser_label, "");
}

TEST(LRGCParams, RangeLimitsOutOfOrderAreErrors)
{
	for (const char* bad : {"min_range_m = -0.1", "max_range_m = -1", "min_range_m = 2\nmax_range_m = 1"})
	{
		mrpt::config::CConfigFileMemory mem(std::string("[MapBuilder]\n") + bad + "\n");
		lrgc::TLRGCParams p;
		EXPECT_THROW(p.loadFromConfigFile(mem, {}), std::exception) << bad;
	}
}
