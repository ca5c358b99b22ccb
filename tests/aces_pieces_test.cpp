/* Maps of several pieces (issue 29 item 1, done-when) on the ACES log: session A, scans
 * [0, 1474), is mapped; session B starts 42 m away from any pose of A, in its own odometry
 * frame (its odometry moved by +37 m, -12 m, 130 deg: cutCarmenScans), and continues A's map
 * (--initial-map). B is mapped from its first scan as a piece of its own and joined to A's
 * map where global correlation finds it:
 *  - B = scans [2934, end): one map; A's and B's trajectory.tum together score <= 0.0375 m
 *    mean translational relation error (Cartographer on the whole log) over the relations
 *    within the two sessions, >= 99 % of all relations with both ends in a session evaluated,
 *    and those joining the two sessions are about as consistent as in one run of the log;
 *  - B = scans [2934, 3934), which never reaches A's ground: exit 0, its map kept (saved with
 *    A's, stats.json says it was not joined and in which frame it is stated), and its error
 *    over its own relations no worse than 1.1 times that of the same scans mapped alone.
 * Skips where the shared benchmark logs are absent. */
#include <gtest/gtest.h>

#include <algorithm>

#include "aces_sessions.h"
#include "app_runner.h"
#include "carmen_split.h"
#include "test_data.h"

using namespace lrgc::test;

namespace
{

struct TAcesSessionA
{
	std::string dir, relations;
};

TAcesSessionA sessionAMapped(const std::string& name)
{
	TAcesSessionA a{makeTempDir(name), sharedDatasetPath("aces/aces.relations")};
	const std::string log = a.dir + "/aces-a.clf";
	EXPECT_EQ(cutCarmenScans(sharedDatasetPath("aces/aces.clf.gz"), log, 0, kSessionAEnd, {}),
			  kSessionAEnd);
	const auto r =
		runProcess(binaryPath("lrgc-slam"), {"--input", log, "--out", a.dir + "/a", "--quiet"});
	EXPECT_EQ(r.exitCode, 0) << r.output;
	return a;
}

}  // namespace

TEST(AcesPieces, secondSessionStartingOutsideTheMapJoinsIt)
{
	LRGC_SKIP_IF_MISSING(sharedDatasetPath("aces/aces.clf.gz"));
	LRGC_SKIP_IF_MISSING(sharedDatasetPath("aces/aces.relations"));
	const TAcesSessionA a = sessionAMapped("aces_pieces_join");
	const std::string logB = a.dir + "/aces-b.clf";
	cutCarmenScans(sharedDatasetPath("aces/aces.clf.gz"), logB, kSessionBStart, SIZE_MAX,
				   kMoveB);
	const auto r = runProcess(binaryPath("lrgc-slam"), {"--input", logB, "--initial-map",
														a.dir + "/a", "--out", a.dir + "/b"});
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("the log starts at"), std::string::npos) << r.output;
	const std::string stats = readTextFile(a.dir + "/b/stats.json");
	EXPECT_NE(stats.find("\"joined\": true"), std::string::npos) << stats;
	const std::vector<std::string> tums{a.dir + "/a/trajectory.tum",
										a.dir + "/b/trajectory.tum"};
	size_t considered = 0, within = 0, across = 0;
	const auto ev = evaluate(tums, a.relations, a.dir + "/both.tum", considered);
	const auto evWithin =
		evaluate(tums, a.relations, a.dir + "/both.tum", within, Relations::WithinSessions);
	const auto evAcross =
		evaluate(tums, a.relations, a.dir + "/both.tum", across, Relations::AcrossSessions);
	const double coverage = double(ev.errors.size()) / double(std::max<size_t>(considered, 1));
	RecordProperty("mean_trans_m", std::to_string(ev.trans_m.mean));
	RecordProperty("within_sessions_mean_trans_m", std::to_string(evWithin.trans_m.mean));
	RecordProperty("across_sessions_mean_trans_m", std::to_string(evAcross.trans_m.mean));
	RecordProperty("coverage", std::to_string(coverage));
	EXPECT_GT(considered, 900U);
	EXPECT_GT(across, 10U);
	EXPECT_GE(coverage, 0.99);
	// Issue 29's bar, over all the relations with both ends in a session (the 20 that join the
	// sessions included): measured 0.03737 m at the end of stop 36 (within 0.0366, across
	// 0.0742). It sits within the spread of the split's start: 0.0370-0.0379 with B starting at
	// another scan in 2900-3000, and the whole log in one run scores 0.0372 m on the same
	// relations (doc/localization.md "What the joined figure is made of"); a change to mapping
	// that moves it above the bar fails here and must be judged there.
	EXPECT_LE(ev.trans_m.mean, 0.0375);
	EXPECT_LE(evWithin.trans_m.mean, 0.0375);
	EXPECT_LE(evAcross.trans_m.mean, 0.10);
}

TEST(AcesPieces, sessionThatNeverReachesTheMapIsKept)
{
	LRGC_SKIP_IF_MISSING(sharedDatasetPath("aces/aces.clf.gz"));
	LRGC_SKIP_IF_MISSING(sharedDatasetPath("aces/aces.relations"));
	const TAcesSessionA a = sessionAMapped("aces_pieces_apart");
	const std::string logB = a.dir + "/aces-b-short.clf";
	cutCarmenScans(sharedDatasetPath("aces/aces.clf.gz"), logB, kSessionBStart,
				   kSessionBStart + 1000, kMoveB);
	const auto r = runProcess(binaryPath("lrgc-slam"), {"--input", logB, "--initial-map",
														a.dir + "/a", "--out", a.dir + "/b"});
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("was not joined to the map"), std::string::npos) << r.output;
	EXPECT_NE(r.output.find("the log's own frame"), std::string::npos) << r.output;
	EXPECT_TRUE(fileExists(a.dir + "/b/map.simplemap.gz"));
	EXPECT_TRUE(fileExists(a.dir + "/b/graph.lrgc"));
	const std::string stats = readTextFile(a.dir + "/b/stats.json");
	EXPECT_NE(stats.find("\"joined\": false"), std::string::npos) << stats;
	EXPECT_NE(stats.find("\"frame\": \"the log's own frame"), std::string::npos) << stats;

	const auto alone = runProcess(binaryPath("lrgc-slam"),
								  {"--input", logB, "--out", a.dir + "/alone", "--quiet"});
	ASSERT_EQ(alone.exitCode, 0) << alone.output;
	size_t considered = 0, consideredAlone = 0;
	const auto ev =
		evaluate({a.dir + "/b/trajectory.tum"}, a.relations, a.dir + "/b.tum", considered);
	const auto evAlone = evaluate({a.dir + "/alone/trajectory.tum"}, a.relations,
								  a.dir + "/alone.tum", consideredAlone);
	RecordProperty("mean_trans_m", std::to_string(ev.trans_m.mean));
	RecordProperty("alone_mean_trans_m", std::to_string(evAlone.trans_m.mean));
	EXPECT_GT(ev.errors.size(), 150U);
	EXPECT_EQ(ev.errors.size(), evAlone.errors.size());
	EXPECT_LE(ev.trans_m.mean, 1.1 * evAlone.trans_m.mean);
}
