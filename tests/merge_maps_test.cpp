/* lrgc-slam --merge MAP_A MAP_B (issue 29 item 1: "two maps saved by two robots can be merged
 * in one command into one map, when they overlap"), on the ACES log cut as AcesPieces cuts it:
 * A = scans [0, 1474), B = scans [2934, end) in its own odometry frame (moved by +37 m, -12 m,
 * 130 deg), each mapped alone by lrgc-slam, then merged:
 *  - one map in A's frame: A's keyframes as saved, B's trajectory in A's frame; A's and the
 *    merged trajectory.tum together are scored over the relations within the two sessions
 *    and across them, as AcesPieces scores --initial-map (0.0377 m over all);
 *  - the merged map.gridmap.gz and map.simplemap.gz load in MRPT;
 *  - B cut to [2934, 3934), which never reaches A's ground: exit 1, one line naming both
 *    maps, nothing written.
 * Skips where the shared benchmark logs are absent. And without them, on the room of
 * room_log.h: A = the whole drive, B = its second half in another frame; merged, B's poses
 * land on A's poses of the same scans. */
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/core/format.h>
#include <mrpt/serialization/archiveFrom_std_streams.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <filesystem>
#include <regex>

#include "aces_sessions.h"
#include "app_runner.h"
#include "archive_gz.h"
#include "carmen_split.h"
#include "live_sick_run.h"
#include "room_log.h"
#include "test_data.h"

using namespace lrgc::test;

namespace
{

/** The ACES scans [first, end) mapped alone into dir/name (B's odometry moved by kMoveB). */
void mapSession(const std::string& dir, const std::string& name, size_t first, size_t end)
{
	const std::string log = dir + "/" + name + ".clf";
	cutCarmenScans(sharedDatasetPath("aces/aces.clf.gz"), log, first, end,
				   first == 0 ? TOdometryMove{} : kMoveB);
	const auto r = runProcess(binaryPath("lrgc-slam"),
							  {"--input", log, "--out", dir + "/" + name, "--quiet"});
	ASSERT_EQ(r.exitCode, 0) << r.output;
}

/** The largest gap [m] and [rad] between the poses of `tum` and those of `reference` at the
 * same stamps; `matched` the poses compared. */
std::pair<double, double> largestGap(const std::string& tum, const std::string& reference,
									 size_t& matched)
{
	const auto ref = eval::CTrajectory2D::loadFromFile(reference);
	double dxy = 0, dphi = 0;
	matched = 0;
	const auto merged = eval::CTrajectory2D::loadFromFile(tum);
	for (const auto& p : merged.poses())
		if (const auto r = ref.poseAt(p.t); r && r->how == eval::TPoseLookup::Exact)
		{
			++matched;
			dxy = std::max(dxy, std::hypot(p.pose.x - r->pose.x, p.pose.y - r->pose.y));
			dphi = std::max(dphi, std::abs(mrpt::math::wrapToPi(p.pose.phi - r->pose.phi)));
		}
	return {dxy, dphi};
}

/** B's trajectory.tum moved rigidly by stats.json's merge "b_in_a", written to `out`: the map a
 * paste of B by the join alone would give, without the replay's adjustment to A. */
void pasteRigidly(const std::string& tumB, const std::string& stats, const std::string& out)
{
	std::smatch m;
	const std::regex re(
		"\"b_in_a\": \\{\"x\": ([-0-9.]+), \"y\": ([-0-9.]+), \"phi_deg\": ([-0-9.]+)\\}");
	ASSERT_TRUE(std::regex_search(stats, m, re)) << stats;
	const mrpt::poses::CPose2D bInA(std::stod(m[1]), std::stod(m[2]),
									mrpt::DEG2RAD(std::stod(m[3])));
	std::string text;
	const auto b = eval::CTrajectory2D::loadFromFile(tumB);
	for (const auto& p : b.poses())
	{
		const mrpt::poses::CPose2D q = bInA + mrpt::poses::CPose2D(p.pose);
		text += mrpt::format("%.6f %.6f %.6f 0 0 0 %.9f %.9f\n", p.t, q.x(), q.y(),
							 std::sin(q.phi() / 2), std::cos(q.phi() / 2));
	}
	writeTextFile(out, text);
}

class AcesMerge : public ::testing::Test
{
protected:
	/** Session A mapped into m_dir/a, m_dir a folder of this test's own (ctest may run the
	 * tests at once). */
	void SetUp() override
	{
		LRGC_SKIP_IF_MISSING(sharedDatasetPath("aces/aces.clf.gz"));
		LRGC_SKIP_IF_MISSING(sharedDatasetPath("aces/aces.relations"));
		m_dir = makeTempDir(std::string("aces_merge_") +
							::testing::UnitTest::GetInstance()->current_test_info()->name());
		mapSession(m_dir, "a", 0, kSessionAEnd);
	}
	std::string m_dir;
};
}  // namespace

TEST_F(AcesMerge, overlappingMapsBecomeOneInTheFirstsFrame)
{
	mapSession(m_dir, "b", kSessionBStart, SIZE_MAX);
	const std::string a = m_dir + "/a", b = m_dir + "/b", m = m_dir + "/merged";
	const auto r = runProcess(binaryPath("lrgc-slam"), {"--merge", a, b, "--out", m});
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("placed in '" + a + "' at (A <- B)"), std::string::npos)
		<< r.output;
	const std::string stats = readTextFile(m + "/stats.json");
	EXPECT_NE(stats.find("\"merge\": {\"map_a\""), std::string::npos) << stats;
	EXPECT_NE(stats.find("\"joined\": true, \"joined_after_keyframes\""), std::string::npos)
		<< stats;

	// A's keyframes are kept as saved; the merged map holds them and B's.
	mrpt::maps::CSimpleMap keyframesA, merged;
	readArchiveGz(a + "/map.simplemap.gz", keyframesA);
	readArchiveGz(m + "/map.simplemap.gz", merged);
	ASSERT_GT(merged.size(), keyframesA.size());
	for (size_t i = 0; i < keyframesA.size(); ++i)
		EXPECT_EQ(std::get<0>(merged.get(i))->getMeanVal(),
				  std::get<0>(keyframesA.get(i))->getMeanVal())
			<< "keyframe " << i;
	mrpt::maps::COccupancyGridMap2D grid;  // MRPT reads the map pf-localization loads
	readArchiveGz(m + "/map.gridmap.gz", grid);
	EXPECT_GT(grid.getSizeX() * grid.getSizeY(), 0u);

	const std::string relations = sharedDatasetPath("aces/aces.relations");
	const std::vector<std::string> tums{a + "/trajectory.tum", m + "/trajectory.tum"};
	size_t considered = 0, within = 0, across = 0;
	const auto ev = evaluate(tums, relations, m_dir + "/both.tum", considered);
	const auto evWithin =
		evaluate(tums, relations, m_dir + "/both.tum", within, Relations::WithinSessions);
	const auto evAcross =
		evaluate(tums, relations, m_dir + "/both.tum", across, Relations::AcrossSessions);
	const double coverage = double(ev.errors.size()) / double(std::max<size_t>(considered, 1));
	RecordProperty("mean_trans_m", std::to_string(ev.trans_m.mean));
	RecordProperty("within_sessions_mean_trans_m", std::to_string(evWithin.trans_m.mean));
	RecordProperty("across_sessions_mean_trans_m", std::to_string(evAcross.trans_m.mean));
	RecordProperty("coverage", std::to_string(coverage));
	std::cout << "merged A + B: " << ev.trans_m.mean << " m over " << ev.errors.size() << " of "
			  << considered << " relations; within sessions " << evWithin.trans_m.mean
			  << " m, across (" << across << ") " << evAcross.trans_m.mean << " m\n";
	EXPECT_GT(considered, 900U);
	EXPECT_GT(across, 10U);
	EXPECT_GE(coverage, 0.99);
	// Measured: 0.0383 m over all 985, 0.0374 within the sessions, 0.0795 over the 20 across
	// (--initial-map, AcesPieces: 0.0377 / 0.0369 / 0.0786; one run of the whole log: 0.0375
	// over all, 0.0795 across); at the end of stop 36 0.0385 / 0.0377 / 0.0767, as each
	// change to mapping moves B's loops (the six starts of doc/localization.md spread 0.0009
	// m). Issue 29 sets no bar for a merge; this one holds the merged map at one run's level
	// (B mapped alone: 0.0360-0.0367 within B), far from a paste's:
	EXPECT_LE(evWithin.trans_m.mean, 0.039);
	EXPECT_LE(evAcross.trans_m.mean, 0.10);
	// The replay's reason to be: B pasted rigidly by the same join scores 0.509 m across.
	pasteRigidly(b + "/trajectory.tum", stats, m_dir + "/pasted.tum");
	const auto evPasted = evaluate({a + "/trajectory.tum", m_dir + "/pasted.tum"}, relations,
								   m_dir + "/both.tum", across, Relations::AcrossSessions);
	RecordProperty("pasted_across_sessions_mean_trans_m",
				   std::to_string(evPasted.trans_m.mean));
	EXPECT_LT(evAcross.trans_m.mean, 0.5 * evPasted.trans_m.mean);
}

TEST_F(AcesMerge, mapsThatDoNotOverlapAreRefusedAndNothingIsWritten)
{
	mapSession(m_dir, "b-short", kSessionBStart, kSessionBStart + 1000);
	const std::string a = m_dir + "/a", b = m_dir + "/b-short", m = m_dir + "/not-merged";
	const auto r = runProcess(binaryPath("lrgc-slam"), {"--merge", a, b, "--out", m});
	EXPECT_EQ(r.exitCode, 1) << r.output;
	EXPECT_NE(r.output.find("lrgc-slam: the maps '" + a + "' and '" + b + "' do not overlap"),
			  std::string::npos)
		<< r.output;
	std::error_code ec;
	EXPECT_TRUE(!std::filesystem::exists(m, ec) || std::filesystem::is_empty(m, ec)) << m;
}

// The room's drive (A) and its second half (B, scans [40, 81), its odometry moved by (5 m,
// -3 m, 57 deg)), each mapped alone, each map in its first scan's frame: B is placed in A's
// frame by (A <- B) = (4 m, 0, 0), its 41 scans (13 keyframes, the others re-hung from them)
// where A put the same scans.
TEST(RoomMerge, secondHalfInItsOwnFrameLandsOnTheFirstMap)
{
	const std::string dir = makeTempDir("room_merge");
	writeTextFile(dir + "/room.clf", roomLog());
	cutCarmenScans(dir + "/room.clf", dir + "/b.clf", 40, SIZE_MAX, {5.0, -3.0, 1.0});
	for (const char* name : {"room", "b"})
	{
		const auto r = runProcess(
			binaryPath("lrgc-slam"),
			{"--input", dir + "/" + name + ".clf", "--out", dir + "/" + name, "--quiet"});
		ASSERT_EQ(r.exitCode, 0) << r.output;
	}
	const auto r = runProcess(binaryPath("lrgc-slam"),
							  {"--merge", dir + "/room", dir + "/b", "--out", dir + "/merged"});
	ASSERT_EQ(r.exitCode, 0) << r.output;
	size_t matched = 0;
	const auto [dxy, dphi] =
		largestGap(dir + "/merged/trajectory.tum", dir + "/room/trajectory.tum", matched);
	EXPECT_EQ(matched, 41U);
	EXPECT_LT(dxy, 0.01) << r.output;  // measured 0.6 mm, 0.001 deg
	EXPECT_LT(dphi, mrpt::DEG2RAD(0.1)) << r.output;
	EXPECT_NE(readTextFile(dir + "/merged/stats.json").find("\"joined\": true"),
			  std::string::npos);
}

// Bad inputs: one line naming the file (exit 1) or the option (exit 2); nothing written.
TEST(RoomMerge, badInputsAreNamedAndNothingIsWritten)
{
	const std::string dir = makeTempDir("room_merge_bad");
	writeTextFile(dir + "/room.clf", roomLog());
	const auto mapped =
		runProcess(binaryPath("lrgc-slam"),
				   {"--input", dir + "/room.clf", "--out", dir + "/room", "--quiet"});
	ASSERT_EQ(mapped.exitCode, 0) << mapped.output;
	writeTextFile(dir + "/broken.simplemap", "not a simplemap\n");
	const std::string room = dir + "/room", out = dir + "/out";
	const struct
	{
		std::vector<std::string> args;
		int exitCode;
		std::string says;
	} cases[] = {
		{{"--merge", room, dir + "/missing", "--out", out},
		 1,
		 "'" + dir + "/missing': no such"},
		{{"--merge", dir + "/broken.simplemap", room, "--out", out},
		 1,
		 "'" + dir + "/broken.simplemap': not a readable MRPT CSimpleMap"},
		{{"--merge", room, "--out", out}, 2, "--merge needs two values"},
		{{"--merge", room, room}, 2, "--merge needs --out DIR"},
		{{"--merge", room, room, "--input", dir + "/room.clf", "--out", out},
		 2,
		 "--merge takes no --input"},
	};
	for (const auto& c : cases)
	{
		const auto r = runProcess(binaryPath("lrgc-slam"), c.args);
		EXPECT_EQ(r.exitCode, c.exitCode) << r.output;
		EXPECT_NE(r.output.find(c.says), std::string::npos) << r.output;
		EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
		EXPECT_FALSE(fileExists(out)) << r.output;
	}
}

// A map merged with its own keyframes as a .simplemap file (no graph, no trajectory.tum): B is
// placed on A at about the identity, and the keyframes on ground A covers are reused, so the
// merged map hardly grows. Measured: 159 + 2 keyframes, (A <- B) 1.1 cm, 0.01 deg off; of B's
// 159 keyframes 153 within 1 cm of A's, 158 within 3 cm, and one, the scan the replay could
// not match (unmatched_scans 1), 0.28 m off.
TEST(SenaMerge, aMapMergedWithItselfLandsOnItselfAndHardlyGrows)
{
	LRGC_SKIP_IF_MISSING(senaRawlogPath());
	const std::string dir = makeTempDir("sena_merge");
	const auto mapped = runProcess(
		binaryPath("lrgc-slam"), {"--input", senaRawlogPath(), "--out", dir + "/a", "--quiet"});
	ASSERT_EQ(mapped.exitCode, 0) << mapped.output;
	const auto r = runProcess(
		binaryPath("lrgc-slam"),
		{"--merge", dir + "/a", dir + "/a/map.simplemap.gz", "--out", dir + "/m", "--quiet"});
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const std::string stats = readTextFile(dir + "/m/stats.json");
	const long keyframesA = jsonInt(readTextFile(dir + "/a/stats.json"), "keyframes");
	EXPECT_LE(jsonInt(stats, "keyframes"), keyframesA + keyframesA / 20) << stats;
	// B's trajectory: A's keyframes, each where A has it.
	const auto a = eval::CTrajectory2D::loadFromFile(dir + "/a/trajectory.tum");
	const auto m = eval::CTrajectory2D::loadFromFile(dir + "/m/trajectory.tum");
	ASSERT_EQ(long(m.size()), keyframesA);
	size_t close = 0;
	for (const auto& p : m.poses())
		if (const auto q = a.poseAt(p.t); q && q->how == eval::TPoseLookup::Exact)
			close +=
				std::hypot(p.pose.x - q->pose.x, p.pose.y - q->pose.y) < 0.03 &&
				std::abs(mrpt::math::wrapToPi(p.pose.phi - q->pose.phi)) < mrpt::DEG2RAD(0.5);
	EXPECT_GE(double(close), 0.98 * double(keyframesA));
}
