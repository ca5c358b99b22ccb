/* The strict .ini readers: what each type accepts, and errors that name the section, the key,
 * the value and the type expected. */
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <lrgc/common/params_io.h>

#include <string>

namespace
{
using mrpt::config::CConfigFileMemory;

CConfigFileMemory ini(const std::string& value)
{
	return CConfigFileMemory("[Stage]\nkey = " + value + "\n");
}

// The message of the exception `read` throws, or "" if it throws none.
template <class Read>
std::string errorOf(Read read)
{
	try
	{
		read();
	}
	catch (const std::exception& e)
	{
		return e.what();
	}
	return {};
}

void expectRejected(const std::string& message, const std::string& value, const char* type)
{
	ASSERT_FALSE(message.empty()) << "'" << value << "' accepted";
	EXPECT_NE(message.find("[Stage] key"), std::string::npos) << message;
	EXPECT_NE(message.find("'" + value + "'"), std::string::npos) << message;
	EXPECT_NE(message.find(type), std::string::npos) << message;
}
}  // namespace

TEST(ParamsIo, AnAbsentKeyKeepsTheCurrentValue)
{
	const CConfigFileMemory empty("[Stage]\nother = 1\n");
	EXPECT_EQ(lrgc::readDouble(empty, "Stage", "key", 0.25), 0.25);
	EXPECT_EQ(lrgc::readInt(empty, "Stage", "key", -4), -4);
	EXPECT_EQ(lrgc::readCount(empty, "Stage", "key", 9u), 9u);
	EXPECT_EQ(lrgc::readBool(empty, "Stage", "key", true), true);
}

TEST(ParamsIo, NumbersParseFullyWithBlanksAndACommentAround)
{
	EXPECT_EQ(lrgc::readDouble(ini("0.5"), "Stage", "key", 0), 0.5);
	EXPECT_EQ(lrgc::readDouble(ini("  -2   // [m] a comment"), "Stage", "key", 0), -2);
	EXPECT_EQ(lrgc::readDouble(ini("1e-3"), "Stage", "key", 0), 1e-3);
	EXPECT_EQ(lrgc::readDouble(ini("+7.5"), "Stage", "key", 0), 7.5);
	EXPECT_EQ(lrgc::readDouble(ini("1.000000e-06"), "Stage", "key", 0), 1e-6);
	for (const std::string bad : {"abc", "0,5", "1.5x", "", "inf", "nan", "+-1", "0x10", "1 2"})
		expectRejected(errorOf([&] { lrgc::readDouble(ini(bad), "Stage", "key", 0); }), bad,
					   "a number");
}

TEST(ParamsIo, WholeNumbersMustBeWhole)
{
	EXPECT_EQ(lrgc::readInt(ini("-3"), "Stage", "key", 0), -3);
	EXPECT_EQ(lrgc::readCount(ini("12 // keyframes"), "Stage", "key", 0), 12u);
	EXPECT_EQ(lrgc::readCount(ini("0"), "Stage", "key", 5), 0u);
	for (const std::string bad : {"2.5", "12.7", "7.0", "1e3", "abc", "", "99999999999"})
		expectRejected(errorOf([&] { lrgc::readInt(ini(bad), "Stage", "key", 0); }), bad,
					   "a whole number");
	for (const std::string bad : {"2.5", "-1", "1e3", "abc", ""})
		expectRejected(errorOf([&] { lrgc::readCount(ini(bad), "Stage", "key", 0); }), bad,
					   "a whole number >= 0");
}

TEST(ParamsIo, BooleansAreTrueFalseYesNoOneZeroInAnyCase)
{
	for (const std::string yes : {"true", "TRUE", "Yes", "1"})
		EXPECT_TRUE(lrgc::readBool(ini(yes), "Stage", "key", false)) << yes;
	for (const std::string no : {"false", "False", "NO", "0 // off"})
		EXPECT_FALSE(lrgc::readBool(ini(no), "Stage", "key", true)) << no;
	for (const std::string bad : {"on", "off", "maybe", "2", "", "truee"})
		expectRejected(errorOf([&] { lrgc::readBool(ini(bad), "Stage", "key", false); }), bad,
					   "a boolean");
}

TEST(ParamsIo, ErrorMessagesNameTheirSectionAndKeyForALineNumber)
{
	const auto placeOf = [](const std::string& message)
	{
		const auto p = lrgc::paramPlaceOf(message);
		return p ? "[" + p->section + "] " + p->key : std::string("none");
	};
	EXPECT_EQ(placeOf(errorOf([] { lrgc::readDouble(ini("abc"), "Stage", "key", 0); })),
			  "[Stage] key");
	EXPECT_EQ(
		placeOf(errorOf([] { lrgc::requireParam(false, "Stage", "key", "must be > 0"); })),
		"[Stage] key");
	struct TOneKey : mrpt::config::CLoadableOptions
	{
		void loadFromConfigFile(const mrpt::config::CConfigFileBase&,
								const std::string&) override
		{
		}
		void saveToConfigFile(mrpt::config::CConfigFileBase& c,
							  const std::string& s) const override
		{
			c.write(s, "key", 1);
		}
	};
	const CConfigFileMemory misspelt("[Stage]\nkye = 1\n");
	EXPECT_EQ(placeOf(errorOf([&] { lrgc::rejectUnknownKeys(TOneKey{}, misspelt, "Stage"); })),
			  "[Stage] kye");
	EXPECT_EQ(placeOf("Unknown section [Stagee] in the configuration"), "[Stagee] ");
	EXPECT_EQ(placeOf("something else [Stage] key: went wrong"), "none");
}
