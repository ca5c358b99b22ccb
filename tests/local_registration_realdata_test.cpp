/* Local registration alone (`[MapBuilder] loop_closing = false`, defaults otherwise) on the
 * three benchmark logs must beat published scan matching (issue 11): mean relation error
 * below 0.220 m on Intel, 0.173 m on ACES and 0.106 m on MIT-CSAIL (Kuemmerle et al. 2009,
 * table of scan matching). With a 10-keyframe window whatever the prior, MIT-CSAIL gave
 * 0.119 m; with window_size 15 where the log has odometry 0.100 m (Intel 0.133, ACES
 * 0.159; doc/generalisation.md). Skips where the shared benchmark logs are absent. */
#include <gtest/gtest.h>
#include <lrgc_apps/eval/relation_metric.h>
#include <lrgc_apps/eval/trajectory.h>

#include "app_runner.h"
#include "test_data.h"

using namespace lrgc::test;
namespace eval = lrgc::apps::eval;

namespace
{
struct TPublished
{
	const char* log;
	double scanMatchingError;  //!< [m] published mean translational relation error
};

class LocalRegistrationRealData : public ::testing::TestWithParam<TPublished>
{
};
}  // namespace

TEST_P(LocalRegistrationRealData, aloneBeatsPublishedScanMatching)
{
	const std::string name = GetParam().log;
	const std::string log = sharedDatasetPath(name + "/" + name + ".clf.gz");
	const std::string relations = sharedDatasetPath(name + "/" + name + ".relations");
	LRGC_SKIP_IF_MISSING(log);
	LRGC_SKIP_IF_MISSING(relations);
	const std::string dir = makeTempDir("local_only_" + name);
	writeTextFile(dir + "/local.ini", "[MapBuilder]\nloop_closing = false\n");
	const auto r = runProcess(
		binaryPath("lrgc-slam"),
		{"--input", log, "--config", dir + "/local.ini", "--out", dir + "/out", "--quiet"});
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const auto trajectory = eval::CTrajectory2D::loadFromFile(dir + "/out/trajectory.tum");
	const auto result = eval::evaluateRelations(trajectory, eval::loadRelations(relations));
	EXPECT_TRUE(result.unmatched.empty());
	RecordProperty("relation_error_m", std::to_string(result.trans_m.mean));
	EXPECT_LT(result.trans_m.mean, GetParam().scanMatchingError) << name;
}

INSTANTIATE_TEST_SUITE_P(BenchmarkLogs, LocalRegistrationRealData,
						 ::testing::Values(TPublished{"intel", 0.220},
										   TPublished{"aces", 0.173},
										   TPublished{"mit-csail", 0.106}),
						 [](const ::testing::TestParamInfo<TPublished>& p)
						 {
							 std::string s = p.param.log;
							 for (char& c : s)
								 if (c == '-') c = '_';
							 return s;
						 });
