/* Continuing and localising on a saved map with a real log (issue 14, done-when): the Intel
 * log split in two halves by file lines. The first half is mapped; the second half
 *  - continues that map (--initial-map): its start in the old map is found by global
 *    correlation, its loops to the old map close, and the two trajectory.tum files together
 *    must score <= 0.0229 m mean translational relation error on intel.relations (the whole
 *    log mapped in one run scores 0.013 m, doc/benchmarks.md), every relation evaluated;
 *  - is localised on the first half's map (--localize, no start pose given): together
 *    <= 0.030 m, every relation evaluated.
 * Skips where the shared benchmark logs are absent. */
#include <gtest/gtest.h>
#include <lrgc_apps/eval/relation_metric.h>
#include <lrgc_apps/eval/trajectory.h>

#include "app_runner.h"
#include "carmen_split.h"
#include "test_data.h"

using namespace lrgc::test;
namespace eval = lrgc::apps::eval;

namespace
{
struct TIntelHalves
{
	std::string dir, first, second, relations;
};

TIntelHalves intelHalvesMapped(const std::string& name)
{
	TIntelHalves h;
	h.dir = makeTempDir(name);
	h.first = h.dir + "/intel-first.clf";
	h.second = h.dir + "/intel-second.clf";
	h.relations = sharedDatasetPath("intel/intel.relations");
	const auto counts =
		splitCarmenLog(sharedDatasetPath("intel/intel.clf.gz"), h.first, h.second);
	EXPECT_GT(counts.firstDataLines, 20000U);
	const auto r = runProcess(binaryPath("lrgc-slam"),
							  {"--input", h.first, "--out", h.dir + "/first", "--quiet"});
	EXPECT_EQ(r.exitCode, 0) << r.output;
	return h;
}

/** The relation metric of the two trajectory files concatenated (lrgc-eval's code). */
eval::TRelationEvaluation evaluateTogether(const TIntelHalves& h, const std::string& secondDir)
{
	const std::string both = h.dir + "/" + "both.tum";
	writeTextFile(both, readTextFile(h.dir + "/first/trajectory.tum") +
							readTextFile(secondDir + "/trajectory.tum"));
	return eval::evaluateRelations(eval::CTrajectory2D::loadFromFile(both),
								   eval::loadRelations(h.relations));
}
}  // namespace

TEST(IntelSplit, secondHalfContinuesTheFirstHalfsMap)
{
	LRGC_SKIP_IF_MISSING(sharedDatasetPath("intel/intel.clf.gz"));
	LRGC_SKIP_IF_MISSING(sharedDatasetPath("intel/intel.relations"));
	const TIntelHalves h = intelHalvesMapped("intel_split_continue");
	const auto r = runProcess(binaryPath("lrgc-slam"),
							  {"--input", h.second, "--initial-map", h.dir + "/first", "--out",
							   h.dir + "/second", "--quiet"});
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("the log starts at"), std::string::npos) << r.output;
	const auto ev = evaluateTogether(h, h.dir + "/second");
	RecordProperty("mean_trans_m", std::to_string(ev.trans_m.mean));
	EXPECT_TRUE(ev.unmatched.empty()) << ev.unmatched.size() << " relations not evaluated";
	EXPECT_LE(ev.trans_m.mean, 0.0229);
	// stats.json says which map was continued and how its start was found.
	const std::string stats = readTextFile(h.dir + "/second/stats.json");
	EXPECT_NE(stats.find("\"initial_map\""), std::string::npos);
}

TEST(IntelSplit, secondHalfIsLocalisedOnTheFirstHalfsMap)
{
	LRGC_SKIP_IF_MISSING(sharedDatasetPath("intel/intel.clf.gz"));
	LRGC_SKIP_IF_MISSING(sharedDatasetPath("intel/intel.relations"));
	const TIntelHalves h = intelHalvesMapped("intel_split_localize");
	const auto r = runProcess(binaryPath("lrgc-slam"),
							  {"--input", h.second, "--localize", h.dir + "/first", "--out",
							   h.dir + "/second", "--quiet"});
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const auto ev = evaluateTogether(h, h.dir + "/second");
	RecordProperty("mean_trans_m", std::to_string(ev.trans_m.mean));
	EXPECT_TRUE(ev.unmatched.empty()) << ev.unmatched.size() << " relations not evaluated";
	EXPECT_LE(ev.trans_m.mean, 0.030);
	// Localisation only: no map written.
	EXPECT_FALSE(fileExists(h.dir + "/second/map.simplemap.gz"));
}
