/* The man pages (doc/man/NAME.1) list every option the programs' --help lists, and groff
 * formats them without a warning (skipped where groff is absent). */
#include <gtest/gtest.h>

#include <regex>
#include <set>
#include <string>

#include "app_runner.h"
#include "test_data.h"

using namespace lrgc::test;

namespace
{
std::string manPage(const std::string& program)
{
	return std::string(LRGC_SOURCE_DIR) + "/doc/man/" + program + ".1";
}

// "--option" words of a text; in troff, written "\-\-option".
std::set<std::string> longOptions(std::string text, bool troff)
{
	if (troff) text = std::regex_replace(text, std::regex(R"(\\-)"), "-");
	std::set<std::string> out;
	const std::regex re("--[a-z][a-z-]*");
	for (auto it = std::sregex_iterator(text.begin(), text.end(), re);
		 it != std::sregex_iterator(); ++it)
		out.insert(it->str());
	return out;
}
}  // namespace

TEST(ManPages, EveryOptionOfHelpIsInTheManPage)
{
	for (const std::string program : {"lrgc-slam", "lrgc-eval", "lrgc-plot"})
	{
		const auto help = runProcess(binaryPath(program), {"--help"});
		ASSERT_EQ(help.exitCode, 0) << program;
		const auto inHelp = longOptions(help.output, false);
		EXPECT_GE(inHelp.size(), 5u) << program;
		const auto inMan = longOptions(readTextFile(manPage(program)), true);
		for (const auto& option : inHelp)
			EXPECT_TRUE(inMan.count(option))
				<< option << " of " << program << " --help is not in " << manPage(program);
	}
	const auto script =
		readTextFile(std::string(LRGC_SOURCE_DIR) + "/scripts/calibrate-sweep-time");
	const auto inMan = longOptions(readTextFile(manPage("calibrate-sweep-time")), true);
	for (const auto& option : longOptions(script.substr(script.find("def main")), false))
		EXPECT_TRUE(inMan.count(option)) << option << " of calibrate-sweep-time";
}

TEST(ManPages, GroffFormatsThemWithoutWarnings)
{
	if (!fileExists("/usr/bin/groff")) GTEST_SKIP() << "groff not installed";
	for (const std::string program :
		 {"lrgc-slam", "lrgc-eval", "lrgc-plot", "calibrate-sweep-time"})
	{
		const auto r =
			runProcess("/usr/bin/groff", {"-man", "-Tutf8", "-ww", "-z", manPage(program)});
		EXPECT_EQ(r.exitCode, 0) << program << ": " << r.output;
		EXPECT_EQ(r.output, "") << program;
	}
}
