/* Sparse scans (issue 28 item 3): each shared log made sparse by bench/make-sparse-log (a scan
 * per metre or 30 degrees of odometry, odometry x1.04 in translation, x1.05 + 0.5 deg/m in
 * rotation, seeded noise; doc/generalisation.md) and mapped by lrgc-slam with the defaults.
 *  - An unmatched scan never bends the map: no relation between scans under 10 s apart is off
 *    by more than 5 deg (a scan left at a prior 15-25 deg wrong shows there: main before the
 *    wide search's second opinion on sparse MIT-CSAIL had 6, and 0.200 m mean).
 *  - The revisits close: loops closed > 0, and the mean relation error within 1.5 times the
 *    dense figure (main's dense trajectory sampled at the kept scans, scored on the same
 *    relations: what the sparse map can reach).
 *  - Loop recall (lrgc-eval --loops, lrgc_apps/eval/loop_recall.h, the glass world's
 *    definition) against the dense log mapped by the same build as the reference, the links
 *    judged by the log's own relations wherever one joins both ends within 20 s: >= 90 % of
 *    the revisited places closed and no kept loop link that the relations call false, on
 *    all four (seed 1, main's dense runs as the reference: 38 / 40, 9 / 9, 9 / 9, 65 / 69;
 *    ACES' dead-end returns and Killian's corridors driven back closed by the revisit
 *    sweep's reach, doc/generalisation.md).
 *    Links judged by the reference alone are only printed: the dense map's own joins can be
 *    a few decimetres off (Killian). The four tests take about 90 s of CPU in all, dense
 *    runs included (Killian's the longest: 86 s wall on a loaded machine).
 * Skips where the shared logs or python3 are absent. */
#include <gtest/gtest.h>
#include <lrgc_apps/eval/loop_recall.h>
#include <lrgc_apps/eval/relation_metric.h>
#include <lrgc_apps/eval/trajectory.h>

#include "app_runner.h"
#include "test_data.h"

#include <cstdlib>
#include <filesystem>
#include <regex>
#include <sstream>

using namespace lrgc::test;
namespace eval = lrgc::apps::eval;
namespace fs = std::filesystem;

namespace
{
bool onPath(const std::string& program)
{
	const char* path = std::getenv("PATH");
	std::istringstream dirs(path ? path : "");
	for (std::string dir; std::getline(dirs, dir, ':');)
		if (!dir.empty() && fs::exists(fs::path(dir) / program)) return true;
	return false;
}

long jsonInt(const std::string& json, const std::string& key)
{
	std::smatch m;
	if (!std::regex_search(json, m, std::regex("\"" + key + "\": (-?[0-9]+)"))) return -1;
	return std::stol(m[1]);
}

struct TSparseCase
{
	const char* name;  //!< folder and file stem under ../shared/datasets
	/** [m] main's dense trajectory (at 639db6f) sampled at the kept scans, scored on the
	 * sparse relations: 0.0229 / 0.0510 / 0.0390 / 0.0406 m. */
	double denseFigure_m;
};

/** Loop recall of the sparse run in dir/out against the dense log mapped now (dir/dense), the
 * links judged by the dense log's relations where they reach. */
eval::TLoopRecall loopRecall(const std::string& dir, const std::string& denseLog,
							 const std::string& denseRelations)
{
	const auto r = runProcess(binaryPath("lrgc-slam"),
							  {"--input", denseLog, "--out", dir + "/dense", "--quiet"});
	EXPECT_EQ(r.exitCode, 0) << r.output;
	eval::TRecallInputs in =
		eval::loadRecallInputs(dir + "/out", dir + "/dense/trajectory.tum");
	const eval::TLoopRecallParams p;
	return eval::evaluateLoopRecall(
		in.graph, in.keyframes, p,
		eval::truthFromRelations(eval::loadRelations(denseRelations), std::move(in.reference),
								 p.relationReach_s));
}

void mapSparseVariant(const TSparseCase& c)
{
	const std::string log = sharedDatasetPath(std::string(c.name) + "/" + c.name + ".clf.gz");
	const std::string rel =
		sharedDatasetPath(std::string(c.name) + "/" + c.name + ".relations");
	LRGC_SKIP_IF_MISSING(log);
	LRGC_SKIP_IF_MISSING(rel);
	if (!onPath("python3")) GTEST_SKIP() << "python3 not on PATH (bench/make-sparse-log)";
	const std::string dir = makeTempDir(std::string("sparse_") + c.name);
	const auto made = runProcess(
		std::string(LRGC_SOURCE_DIR) + "/bench/make-sparse-log",
		{log, dir + "/sparse.clf.gz", "--relations", rel, dir + "/sparse.relations"});
	ASSERT_EQ(made.exitCode, 0) << made.output;
	const auto r = runProcess(binaryPath("lrgc-slam"), {"--input", dir + "/sparse.clf.gz",
														"--out", dir + "/out", "--quiet"});
	ASSERT_EQ(r.exitCode, 0) << r.output;

	const auto trajectory = eval::CTrajectory2D::loadFromFile(dir + "/out/trajectory.tum");
	const auto ev =
		eval::evaluateRelations(trajectory, eval::loadRelations(dir + "/sparse.relations"));
	const std::string stats = readTextFile(dir + "/out/stats.json");
	const long loops = jsonInt(stats, "loop_closures");
	std::cout << c.name << " sparse: " << made.output << "  relation error " << ev.trans_m.mean
			  << " m, " << ev.rot_deg.mean << " deg; short relations " << ev.shortCount << ", "
			  << ev.shortOver2deg << " off by > 2 deg, " << ev.shortOver5deg << " by > 5; "
			  << jsonInt(stats, "unmatched_scans") << " of " << jsonInt(stats, "scans")
			  << " scans unmatched; " << loops << " loops closed\n";

	EXPECT_TRUE(ev.unmatched.empty()) << "every relation is on a kept scan";
	EXPECT_GT(ev.shortCount, 200U);
	EXPECT_EQ(ev.shortOver5deg, 0U) << "a short relation off by > 5 deg: a bent map";
	EXPECT_GT(loops, 0);
	EXPECT_LT(ev.trans_m.mean, 1.5 * c.denseFigure_m);
	const auto recall = loopRecall(dir, log, rel);
	std::cout << eval::recallReport(recall);
	size_t falseByRelations = 0;
	for (const auto& l : recall.loopLinks) falseByRelations += !l.agrees && l.byRelation;
	::testing::Test::RecordProperty("loop_recall", std::to_string(recall.recall()));
	::testing::Test::RecordProperty("false_closures_by_relations",
									std::to_string(falseByRelations));
	EXPECT_GE(recall.recall(), 0.9);
	EXPECT_EQ(falseByRelations, 0U) << eval::recallReport(recall);
}
}  // namespace

TEST(SparseScans, Intel)
{
	mapSparseVariant({"intel", 0.0229});
}
TEST(SparseScans, Aces)
{
	mapSparseVariant({"aces", 0.0510});
}
TEST(SparseScans, MitCsail)
{
	mapSparseVariant({"mit-csail", 0.0390});
}
TEST(SparseScans, MitKillian)
{
	mapSparseVariant({"mit-killian", 0.0406});
}
