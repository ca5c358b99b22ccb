/* lrgc-eval's CLI end to end on small files written by the tests: exit codes, the text
 * report, the JSON report, unmatched relations and malformed inputs. */
#include <gtest/gtest.h>
#include "eval/CEvalApp.h"
#include <mrpt/core/format.h>
#include <test_data.h>

#include <cmath>
#include <fstream>
#include <sstream>

using namespace lrgc::apps::eval;

namespace
{
void writeFile(const std::string& path, const std::string& text)
{
	std::ofstream(path) << text;
}

struct TRun
{
	int code = 0;
	std::string out, err;
};

TRun runEval(const std::vector<std::string>& args)
{
	std::ostringstream out, err;
	TRun r;
	r.code = CEvalApp::run(args, out, err);
	r.out = out.str();
	r.err = err.str();
	return r;
}

bool contains(const std::string& s, const std::string& what)
{
	return s.find(what) != std::string::npos;
}

class EvalApp : public ::testing::Test
{
protected:
	std::string dir, tum, rel;
	void SetUp() override
	{
		dir = lrgc::test::makeTempDir(
			std::string("eval_") +
			::testing::UnitTest::GetInstance()->current_test_info()->name());
		tum = dir + "/t.tum";
		rel = dir + "/r.relations";
		// Straight drive along x, 1 m per second, heading 0 (qw = 1).
		writeFile(tum,
				  "# t x y z qx qy qz qw\n"
				  "100.000000 0 0 0 0 0 0 1\n"
				  "101.000000 1 0 0 0 0 0 1\n"
				  "102.000000 2 0 0 0 0 0 1\n"
				  "103.000000 3 0 0 0 0 0 1\n");
		// Errors: 0.1 m, 0.3 m, and 10 deg; one relation after the end.
		writeFile(rel,
				  "100.00000 101.00000 0.9 0 0 0 0 0\n"
				  "101.00000 103.00000 2.3 0 0 0 0 0\n"
				  "100.50000 102.50000 2.0 0 0 0 0 0.174532925199\n"
				  "102.00000 104.00000 2.0 0 0 0 0 0\n");
	}
};
}  // namespace

TEST_F(EvalApp, RelationsReportAndJson)
{
	const std::string json = dir + "/out.json";
	const auto r = runEval({"--trajectory", tum, "--relations", rel, "--json", json});
	ASSERT_EQ(r.code, 0) << r.err;
	EXPECT_TRUE(
		contains(r.out, "4 relations, 3 used (1 with an interpolated pose), 1 unmatched"))
		<< r.out;
	EXPECT_TRUE(contains(r.out, "unmatched, line 4: t2 = 104.000000 outside")) << r.out;
	// translational errors 0.1, 0.3, |e| of the rotated one:
	// delta = (2,0,0), rel^-1 = R(-10deg)(-2,0) -> e = (2 - 2 cos 10deg, 2 sin 10deg, -10deg).
	const double e3 = std::hypot(2 - 2 * std::cos(M_PI / 18), 2 * std::sin(M_PI / 18));
	const double mean = (0.1 + 0.3 + e3) / 3;
	EXPECT_TRUE(contains(r.out, mrpt::format("mean %.4f", mean))) << r.out;

	std::ifstream in(json);
	std::stringstream ss;
	ss << in.rdbuf();
	const std::string j = ss.str();
	EXPECT_TRUE(contains(j, "\"used\": 3")) << j;
	EXPECT_TRUE(contains(j, "\"unmatched\": 1")) << j;
	EXPECT_TRUE(contains(j, "\"line\": 4")) << j;
	EXPECT_TRUE(contains(j, "\"t2\": 104.000000")) << j;
	EXPECT_TRUE(contains(j, mrpt::format("\"mean\": %.10g", mean))) << j;
	EXPECT_TRUE(contains(j, mrpt::format("\"mean\": %.10g", 10.0 / 3))) << j;  // rot deg
}

TEST_F(EvalApp, GroundTruthAteAndRpe)
{
	const std::string gt = dir + "/gt.txt";
	writeFile(gt, "99.0 0 0 0\n100.0 0 0 0\n101.0 1 0 0\n102.0 2 0 0\n103.0 3 0 0\n");
	const std::string json = dir + "/gt.json";
	const auto r = runEval({"--trajectory", tum, "--ground-truth", gt, "--json", json});
	ASSERT_EQ(r.code, 0) << r.err;
	EXPECT_TRUE(contains(r.out, "5 poses, 4 paired, 1 outside")) << r.out;
	EXPECT_TRUE(contains(r.out, "RPE over 1 step: 4 relations, 3 used")) << r.out;
	std::ifstream in(json);
	std::stringstream ss;
	ss << in.rdbuf();
	EXPECT_TRUE(contains(ss.str(), "\"ate\"")) << ss.str();
	EXPECT_TRUE(contains(ss.str(), "\"rpe_distance\"")) << ss.str();
}

TEST_F(EvalApp, MalformedInputNamesFileAndLine)
{
	writeFile(rel, "100 101 0.9 0 0 0 0 0\n100 101 0.9 0 0 0\n");
	const auto r = runEval({"--trajectory", tum, "--relations", rel});
	EXPECT_EQ(r.code, 1);
	EXPECT_TRUE(contains(r.err, rel + ":2: expected 8 numbers")) << r.err;

	writeFile(tum, "100 0 0 0 0 0 0 1\n101 1 0 0 0 0 zero 1\n");
	const auto s = runEval({"--trajectory", tum, "--relations", rel});
	EXPECT_EQ(s.code, 1);
	EXPECT_TRUE(contains(s.err, tum + ":2: 'zero' is not a finite number")) << s.err;
}

TEST_F(EvalApp, NoRelationMatchedIsAnError)
{
	writeFile(rel, "5 6 1 0 0 0 0 0\n");
	const auto r = runEval({"--trajectory", tum, "--relations", rel});
	EXPECT_EQ(r.code, 1);
	EXPECT_TRUE(contains(r.out, "1 relations, 0 used")) << r.out;
	EXPECT_TRUE(contains(r.err, "no relation could be matched")) << r.err;
}

TEST_F(EvalApp, UsageErrors)
{
	EXPECT_EQ(runEval({}).code, 2);
	EXPECT_EQ(runEval({"--trajectory", tum}).code, 2);  // nothing to compare with
	EXPECT_EQ(runEval({"--trajectory", tum, "--relations"}).code, 2);
	const auto r = runEval({"--trajectory", tum, "--relations", rel, "--bogus"});
	EXPECT_EQ(r.code, 2);
	// One line, as lrgc-slam's, not the whole usage text.
	EXPECT_EQ(r.err,
			  "lrgc-eval: unknown argument '--bogus'; lrgc-eval --help lists the "
			  "options\n");
	EXPECT_EQ(runEval({"--trajectory", tum, "--relations", rel, "--time-tolerance", "x"}).code,
			  2);
	EXPECT_EQ(runEval({"--loops", dir}).code, 2);  // against what?
	const auto noGraph = runEval({"--loops", dir, "--reference", tum});
	EXPECT_EQ(noGraph.code, 1);
	EXPECT_TRUE(contains(noGraph.err, "--loops '" + dir + "': the folder has no"))
		<< noGraph.err;
}

TEST_F(EvalApp, VersionIsLrgcSlams)
{
	const auto r = runEval({"--version"});
	EXPECT_EQ(r.code, 0) << r.err;
	EXPECT_EQ(r.out, std::string("lrgc-eval ") + LRGC_VERSION + "\n");
}

TEST_F(EvalApp, HelpPrintsTheUsageAndSucceeds)
{
	for (const std::string h : {"--help", "-h"})
	{
		const auto r = runEval({h});
		EXPECT_EQ(r.code, 0) << h << ": " << r.err;
		EXPECT_TRUE(contains(r.out, "Usage: lrgc-eval")) << r.out;
		EXPECT_TRUE(r.err.empty()) << r.err;
	}
}
