#include <gtest/gtest.h>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>

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
	p.builder.keyframe_distance_m = 0.00012345;           // [MapBuilder], once padded
	p.optimizer.relative_cost_tolerance = 1.000001e-04;   // [PoseGraphOptimizer]
	p.correlator.blur_sigma_m = 0.1 + 1e-15;              // [PatchCorrelator], once unpadded
	p.matcher.normal_radius_m = 0.123456789012345;        // [ScanMatcher], once "%.10g"
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
		EXPECT_NE(std::string(e.what()).find("keyframe_distance_m"), std::string::npos)
			<< e.what();
	}
}

TEST(LRGCParams, UnknownSectionIsRejected)
{
	mrpt::config::CConfigFileMemory mem("[MapBuilderr]\nkeyframe_distance_m = 1\n");
	EXPECT_THROW(lrgc::rejectUnknownSections(mem, lrgc::TLRGCParams::sectionNames()),
				 std::exception);
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
	EXPECT_NE(small.find("max_pairwise_links: 5 must be below window_size (2) and "
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
	for (const char* bad :
		 {"min_range_m = -0.1", "max_range_m = -1", "min_range_m = 2\nmax_range_m = 1"})
	{
		mrpt::config::CConfigFileMemory mem(std::string("[MapBuilder]\n") + bad + "\n");
		lrgc::TLRGCParams p;
		EXPECT_THROW(p.loadFromConfigFile(mem, {}), std::exception) << bad;
	}
}

// An .ini written before the keys carried their units (share/lrgc/lrgc-default.ini at
// 7c31216, every key) still loads: each old name is read as its new one with a warning naming
// both, and the values are the defaults'.
TEST(LRGCParams, AnOldFullIniLoadsAsTheDefaultsWithAWarningPerRenamedKey)
{
	const std::string path =
		std::string(LRGC_SOURCE_DIR) + "/tests/data/lrgc-default-7c31216.ini";
	const mrpt::config::CConfigFile old(path);
	lrgc::TLRGCParams p;
	const std::vector<std::string> warnings = p.loadReportingRenames(old, {});
	// The defaults, but for the three defaults changed since 7c31216, which the file sets.
	lrgc::TLRGCParams expected;
	expected.revisits.radius_m = 1.0;      // 2 m since stop 35 (RevisitLinkerParams.h)
	expected.revisits.min_index_gap = 40;  // 15 since the revisit sweep's checks (recall2)
	expected.matcher.wide_min_inlier_fraction = 0.45;  // 0.40 since session 64 (the museum)
	EXPECT_EQ(saved(p), saved(expected));
	EXPECT_EQ(warnings.size(), lrgc::TLRGCParams::renamedKeys().size());
	const auto has = [&](const std::string& w)
	{ return std::find(warnings.begin(), warnings.end(), w) != warnings.end(); };
	EXPECT_TRUE(
		has("[MapBuilder] keyframe_distance is now keyframe_distance_m; read as such "
			"(lrgc-slam --write-default-config FILE writes the current names)"));
	EXPECT_TRUE(
		has("[LoopCloser] old_map_exclusion is now old_map_exclusion_keyframes; read as "
			"such (lrgc-slam --write-default-config FILE writes the current names)"));
	for (const auto& w : warnings) EXPECT_EQ(w.find('\n'), std::string::npos) << w;
}

TEST(LRGCParams, AnOldNameReadsAsTheNewOneAndBothNamesAreAnError)
{
	lrgc::TLRGCParams p;
	const auto warnings = p.loadReportingRenames(mrpt::config::CConfigFileMemory(
		"[MapBuilder]\nkeyframe_distance = 0.5\n[LoopCloser]\nmax_window_theta_deg = 20\n"));
	EXPECT_EQ(p.builder.keyframe_distance_m, 0.5);
	EXPECT_EQ(p.loop.max_window_phi, mrpt::DEG2RAD(20.0));
	EXPECT_EQ(warnings.size(), 2u);
	lrgc::TLRGCParams q;
	try
	{
		q.loadReportingRenames(mrpt::config::CConfigFileMemory(
			"[MapBuilder]\nkeyframe_distance = 0.5\nkeyframe_distance_m = 0.4\n"));
		FAIL() << "both names accepted";
	}
	catch (const std::exception& e)
	{
		EXPECT_NE(
			std::string(e.what()).find("[MapBuilder] keyframe_distance_m: set twice, also "
									   "under its old name keyframe_distance"),
			std::string::npos)
			<< e.what();
	}
}

// TLRGCParams' section argument prefixes every stage's section: lrgc's sections can share an
// .ini with another program's (here one with its own [MapBuilder] and keys lrgc does not know).
TEST(LRGCParams, TheSectionArgumentPrefixesEveryStageSection)
{
	lrgc::TLRGCParams p;
	p.builder.keyframe_distance_m = 0.5;
	p.loop.old_map_exclusion_keyframes = 45;
	mrpt::config::CConfigFileMemory mem;
	p.saveToConfigFile(mem, "lrgc_");
	std::vector<std::string> sections;
	mem.getAllSections(sections);
	ASSERT_EQ(sections.size(), lrgc::TLRGCParams::sectionNames().size());
	for (const auto& s : sections) EXPECT_EQ(s.rfind("lrgc_", 0), 0u) << s;

	const std::string text = "[MapBuilder]\nodometry_topic = /odom\n" + mem.getContent();
	lrgc::TLRGCParams q;
	q.loadFromConfigFile(mrpt::config::CConfigFileMemory(text), "lrgc_");
	EXPECT_EQ(saved(q), saved(p));
	// Without the prefix, the other program's [MapBuilder] is read (and its key is unknown).
	lrgc::TLRGCParams r;
	EXPECT_THROW(r.loadFromConfigFile(mrpt::config::CConfigFileMemory(text), {}),
				 std::exception);
	// Errors name the prefixed section.
	try
	{
		lrgc::TLRGCParams t;
		t.loadFromConfigFile(
			mrpt::config::CConfigFileMemory("[lrgc_MapBuilder]\nkeyframe_distance_m = -1\n"),
			"lrgc_");
		FAIL() << "negative keyframe distance accepted";
	}
	catch (const std::exception& e)
	{
		EXPECT_NE(std::string(e.what()).find("[lrgc_MapBuilder] keyframe_distance_m"),
				  std::string::npos)
			<< e.what();
	}
}
