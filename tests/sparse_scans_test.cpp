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
 *    definition) judged by the log's own relations alone (relation_truth.h: the revisits are
 *    where chains of at most 16 relations join keyframes 60 s apart within 2 m, a loop link's
 *    truth is such a chain), so the judge does not move with the build and no dense run is
 *    needed: >= 90 % of the revisited places closed and no kept loop link that the relations
 *    alone call false, on all four (seed 1, main at 37911f0: 37 / 37, 7 / 7, 7 / 7, 56 / 58).
 *    Links with an end at a keyframe no relation names are judged with the map's own poses
 *    bridging it to the nearest one that has a relation (within 10 s) and only printed
 *    (main's Killian: 503 -> 1185, 0.31 m off, across a turn); links no chain reaches are not
 *    judged (main: 36 / 15 / 10 / 45 of 388 / 36 / 37 / 211).
 *    The four tests took 92 s of CPU with a dense run each, 31 s without (loaded machine,
 *    /usr/bin/time; doc/generalisation.md).
 * SparseScans.TurnsOfEightyDegrees: a harsher variant, as a building mapped by users (1.5 m
 * or 80 deg between scans, odometry x1.08, x1.10 + 1 deg/m), the first 300 scans of Killian
 * (half an hour; ~3 s of CPU). There, after 80-105 deg turns at corridor junctions, the plain
 * match agreed with the prior, and the wide search's second opinion turned the scan a right
 * angle further, onto the corridor the window had seen (main at 8d4d809: 0.449 m mean, 81.7 m
 * worst, a short relation off by > 5 deg; the whole variant 72 m mean).
 * Skips where the shared logs or python3 are absent. */
#include <gtest/gtest.h>
#include <lrgc_apps/eval/loop_recall.h>
#include <lrgc_apps/eval/relation_metric.h>
#include <lrgc_apps/eval/relation_truth.h>
#include <lrgc_apps/eval/trajectory.h>

#include "app_runner.h"
#include "carmen_split.h"
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

/** Loop recall of the sparse run in dir/out judged by the log's relations alone
 * (relation_truth.h): no dense run. */
eval::TLoopRecall loopRecall(const std::string& dir, const std::string& relations)
{
	const eval::TRecallInputs in = eval::loadRecallInputs(dir + "/out", "");
	const eval::CRelationTruth truth(eval::loadRelations(relations), in.keyframes);
	return eval::evaluateLoopRecall(in.graph, in.keyframes, truth);
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
	const auto recall = loopRecall(dir, rel);
	std::cout << eval::recallReport(recall);
	size_t falseByRelations = 0;
	for (const auto& l : recall.loopLinks) falseByRelations += !l.agrees && l.byRelation;
	::testing::Test::RecordProperty("loop_recall", std::to_string(recall.recall()));
	::testing::Test::RecordProperty("false_closures_by_relations",
									std::to_string(falseByRelations));
	::testing::Test::RecordProperty("loop_links_not_judged", std::to_string(recall.notJudged));
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

TEST(SparseScans, TurnsOfEightyDegrees)
{
	const std::string log = sharedDatasetPath("mit-killian/mit-killian.clf.gz");
	const std::string rel = sharedDatasetPath("mit-killian/mit-killian.relations");
	LRGC_SKIP_IF_MISSING(log);
	LRGC_SKIP_IF_MISSING(rel);
	if (!onPath("python3")) GTEST_SKIP() << "python3 not on PATH (bench/make-sparse-log)";
	const std::string dir = makeTempDir("sparse_turns");
	const auto made =
		runProcess(std::string(LRGC_SOURCE_DIR) + "/bench/make-sparse-log",
				   {log, dir + "/harsh.clf.gz", "--step-m", "1.5", "--step-deg", "80",
					"--scale", "1.08", "--rot-scale", "1.10", "--bias-deg-per-m", "1.0",
					"--relations", rel, dir + "/harsh.relations"});
	ASSERT_EQ(made.exitCode, 0) << made.output;
	ASSERT_EQ(cutCarmenScans(dir + "/harsh.clf.gz", dir + "/first.clf", 0, 300, {}), 300U);
	const auto r = runProcess(binaryPath("lrgc-slam"), {"--input", dir + "/first.clf", "--out",
														dir + "/out", "--quiet"});
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const auto trajectory = eval::CTrajectory2D::loadFromFile(dir + "/out/trajectory.tum");
	// Relations beyond the 300 scans are left unmatched.
	const auto ev =
		eval::evaluateRelations(trajectory, eval::loadRelations(dir + "/harsh.relations"));
	std::cout << "first 300 scans: relation error " << ev.trans_m.mean << " m (max "
			  << ev.trans_m.max << "); short relations " << ev.shortCount << ", "
			  << ev.shortOver5deg << " off by > 5 deg\n";
	EXPECT_GT(ev.shortCount, 200U);
	EXPECT_EQ(ev.shortOver5deg, 0U) << "a scan turned a right angle: a bent map";
	EXPECT_LT(ev.trans_m.max, 3.0);
	EXPECT_LT(ev.trans_m.mean, 0.15);
}
