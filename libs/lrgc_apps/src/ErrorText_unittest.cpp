/* oneLineError / oneLineText: what lrgc-slam prints of an exception fits on one line. */
#include "ErrorText.h"

#include <gtest/gtest.h>
#include <mrpt/core/exceptions.h>

#include <stdexcept>

namespace
{
template <class F>
std::string oneLineOf(F&& f)
{
	try
	{
		f();
	}
	catch (const std::exception& e)
	{
		return lrgc::apps::oneLineError(e);
	}
	return "no exception";
}

template <typename T>
void throwFromTemplate(T)  // __PRETTY_FUNCTION__ holds brackets: "[with T = double]"
{
	THROW_EXCEPTION("Invalid value for [MapBuilder] keyframe_distance_m: must be > 0");
}
}  // namespace

using lrgc::apps::oneLineError;
using lrgc::apps::oneLineText;

TEST(ErrorText, MrptExceptionWithoutBannerLocationAndBacktrace)
{
	EXPECT_EQ(
		oneLineOf([] { THROW_EXCEPTION_FMT("Unknown key '%s' in section [%s]", "k", "S"); }),
		"Unknown key 'k' in section [S]");
	EXPECT_EQ(oneLineOf([] { throwFromTemplate(1.0); }),
			  "Invalid value for [MapBuilder] keyframe_distance_m: must be > 0");
	EXPECT_EQ(oneLineOf([] { ASSERT_EQUAL_(1, 2); }).find('\n'), std::string::npos);
}

TEST(ErrorText, NonMrptExceptionIsItsMessage)
{
	EXPECT_EQ(oneLineError(std::runtime_error("log.clf: cannot open: no such file")),
			  "log.clf: cannot open: no such file");
	EXPECT_EQ(oneLineError(std::runtime_error("two\nlines")), "two; lines");
	// What mrpt::exception_to_str() makes of it, as found in older texts.
	EXPECT_EQ(oneLineText("==== non-MRPT exception ====\nlog.clf: cannot open\n"),
			  "log.clf: cannot open");
}

TEST(ErrorText, NestedExceptionKeepsEveryMessage)
{
	const std::string s = oneLineOf(
		[]
		{
			try
			{
				THROW_EXCEPTION("inner problem: port busy");
			}
			catch (const std::exception& e)
			{
				THROW_EXCEPTION(std::string("outer: cannot start (LASER): ") + e.what());
			}
		});
	EXPECT_NE(s.find("outer: cannot start (LASER)"), std::string::npos) << s;
	EXPECT_NE(s.find("inner problem: port busy"), std::string::npos) << s;
	EXPECT_EQ(s.find("===="), std::string::npos) << s;
	EXPECT_EQ(s.find("Call stack"), std::string::npos) << s;
	EXPECT_EQ(s.find('\n'), std::string::npos) << s;
	EXPECT_EQ(oneLineText("[CLMS100ETH] ERROR:\n==== MRPT exception ====\nMessage:  refused.\n"
						  "Location: a.cpp:1\nCall stack backtrace:\n[0 ] 0x1\n"),
			  "[CLMS100ETH] ERROR: refused.");
}
