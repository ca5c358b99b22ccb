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
	p.builder.keyframe_distance = 0.42;
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
	mrpt::config::CConfigFileMemory mem("[MapBuilder]\nkeyframe_distance = -1\n");
	lrgc::TLRGCParams p;
	try
	{
		p.loadFromConfigFile(mem, {});
		FAIL() << "negative keyframe_distance accepted";
	}
	catch (const std::exception& e)
	{
		EXPECT_NE(std::string(e.what()).find("keyframe_distance"), std::string::npos) << e.what();
	}
}

TEST(LRGCParams, UnknownSectionIsRejected)
{
	mrpt::config::CConfigFileMemory mem("[MapBuilderr]\nkeyframe_distance = 1\n");
	EXPECT_THROW(lrgc::rejectUnknownSections(mem, lrgc::TLRGCParams::sectionNames()), std::exception);
	mrpt::config::CConfigFileMemory ok("[MapBuilder]\nkeyframe_distance = 1\n");
	EXPECT_NO_THROW(lrgc::rejectUnknownSections(ok, lrgc::TLRGCParams::sectionNames()));
}
