/* End to end, live, on a saved map (issue 29 item 3): lrgc-slam --live with --localize MAP and
 * with --initial-map MAP, the scans coming from MRPT's CLMS100Eth driver reading the LMS1xx
 * emulator, which serves SENA's scans (tests/support/lms1xx_emulator.h).
 *
 * The truth is SENA mapped offline from its rawlog (odometry, 80 m ranges): the emulator's
 * scan i is the offline run's scan i + 1 (lrgc's reader also maps SENA's first frame), and a
 * map saved from that run is in the same frame. The live scans start halfway through SENA, so
 * the robot's start in the map is unknown and found by global localisation. Checked: the live
 * poses lie on the truth (by index when every scan arrived), the outputs exist, load and
 * agree, the map is never changed by --localize and grows under --initial-map. And the first
 * signal cuts a long global search short in a live run as in an offline one.
 *
 * Timing: CLMS100Eth's start-up takes about 15 s, so each test takes 25 to 60 s. The only
 * duration asserted is the stop's, with a wide bound (see the test).
 */
#include <gtest/gtest.h>
#include <lrgc_apps/io/LogReader.h>
#include <mrpt/graphs/CNetworkOfPoses.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/serialization/CArchive.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <thread>

#include "app_runner.h"
#include "child_process.h"
#include "live_sick_run.h"
#include "lms1xx_emulator.h"
#include "test_data.h"

namespace fs = std::filesystem;
using namespace lrgc::test;

namespace
{
using TRows = std::vector<std::vector<double>>;

/** Heading [rad] of a TUM row (yaw-only quaternion). */
double yawOf(const std::vector<double>& row)
{
	return 2 * std::atan2(row[6], row[7]);
}

/** Position [m] and heading [rad] errors of `live` (rows of the scans served from the
 * emulator's scan `first` on) against the truth (offline SENA: emulator scan i = row i + 1).
 * Paired by index when every scan has a row, else each live pose against the truth pose
 * nearest to it (a weaker check: any place on the path passes). */
std::vector<std::pair<double, double>> poseErrors(const TRows& live, const TRows& truth,
												  size_t first, size_t served)
{
	std::vector<std::pair<double, double>> errors;
	for (size_t k = 0; k < live.size(); ++k)
	{
		size_t t = first + k + 1;
		if (live.size() != served)
		{
			double best = 1e9;
			for (size_t i = 0; i < truth.size(); ++i)
				if (const double d =
						std::hypot(live[k][1] - truth[i][1], live[k][2] - truth[i][2]);
					d < best)
					best = d, t = i;
		}
		errors.emplace_back(std::hypot(live[k][1] - truth[t][1], live[k][2] - truth[t][2]),
							std::abs(mrpt::math::wrapToPi(yawOf(live[k]) - yawOf(truth[t]))));
	}
	return errors;
}

/** The robot is located: over the second half of the run 95 % of the poses lie within 0.1 m
 * of the truth and none is off by 0.1 rad, the last 10 all within 0.1 m. The first half may
 * hold a wrong start, found wrong and corrected (measured, on a loaded machine: a start 0.06 m
 * off, tracking then lost up to 2.6 m, a kidnap detected after 3 scans and relocalised 1.4 s
 * later; events that stats.json reports); without it 111 of 112 poses were within 0.1 m. */
void expectLocated(const std::vector<std::pair<double, double>>& errors)
{
	ASSERT_GE(errors.size(), 20u);
	const size_t half = errors.size() / 2;
	size_t close = 0, closeLate = 0;
	double worstXY = 0, worstPhiLate = 0;
	for (size_t k = 0; k < errors.size(); ++k)
	{
		const auto [xy, phi] = errors[k];
		close += xy <= 0.1, worstXY = std::max(worstXY, xy);
		if (k < half) continue;
		closeLate += xy <= 0.1, worstPhiLate = std::max(worstPhiLate, phi);
		if (k + 10 >= errors.size())
		{
			EXPECT_LE(xy, 0.1) << "pose " << k << " of the last 10";
		}
	}
	EXPECT_GE(closeLate, 0.95 * (errors.size() - half)) << "second half within 0.1 m";
	EXPECT_LT(worstPhiLate, 0.1) << "largest heading error of the second half [rad]";
	GTEST_LOG_(INFO) << close << " of " << errors.size()
					 << " poses within 0.1 m of the offline SENA run (second half: "
					 << closeLate << " of " << errors.size() - half << "); worst " << worstXY
					 << " m";
}

/** SENA's first `entries` log entries as a rawlog (actions and sensory frames, as read). */
void writeSenaPrefix(const std::string& path, size_t entries)
{
	const auto reader = lrgc::apps::openLog(senaRawlogPath());
	mrpt::io::CFileGZOutputStream file(path);
	auto out = mrpt::serialization::archiveFrom(file);
	for (size_t i = 0; i < entries; ++i)
	{
		auto e = reader->next();
		ASSERT_TRUE(e.has_value());
		out << *e->actions << *e->observations;
	}
}

/** Runs lrgc-slam --live with `args` until the emulator has served every scan and the driver
 * noticed the closed connection, then SIGTERM; returns the exit status. */
std::optional<int> runUntilServed(const TLiveRunDirs& d, const CLms1xxEmulator& emu,
								  const std::vector<std::string>& args)
{
	std::vector<std::string> all = {"--live", d.sensors, "--config", d.config, "--out", d.out};
	all.insert(all.end(), args.begin(), args.end());
	CChildProcess app(binaryPath("lrgc-slam"), all, d.dir + "/live.log");
	if (!waitUntil([&] { return emu.finished(); }, kLiveStartupBound + 120) ||
		!app.waitForOutput("sent no valid data", 60))
	{
		ADD_FAILURE() << "the emulator's scans were not all taken\n" << app.output();
		return std::nullopt;
	}
	app.signal(SIGTERM);
	const auto rc = app.waitExit(120);
	EXPECT_TRUE(rc.has_value()) << app.output();
	if (rc != 0) ADD_FAILURE() << app.output();
	return rc;
}

class LiveSickSavedMap : public ::testing::Test
{
protected:
	void SetUp() override
	{
		LRGC_SKIP_IF_MISSING(senaRawlogPath());
		m_rec = lms1xxScansFromRawlog(senaRawlogPath());
		ASSERT_GT(m_rec.scans.size(), 200u);
		m_dir = makeTempDir("live_saved_map_" + std::to_string(::getpid()));
		const auto r = runProcess(binaryPath("lrgc-slam"), {"--input", senaRawlogPath(),
															"--out", m_dir + "/sena", "-q"});
		ASSERT_EQ(r.exitCode, 0) << r.output;
		m_truth = readTum(m_dir + "/sena/trajectory.tum");
		ASSERT_EQ(m_truth.size(), m_rec.scans.size() + 1);
	}
	/** The emulator's scans from `first` on. */
	std::vector<TLms1xxScan> scansFrom(size_t first) const
	{
		return {m_rec.scans.begin() + first, m_rec.scans.end()};
	}

	TLms1xxRecording m_rec;
	std::string m_dir;  //!< holds sena/: SENA mapped offline
	TRows m_truth;      //!< sena/trajectory.tum
};
}  // namespace

// Localisation on SENA's map of live scans that start halfway round the loop: global
// localisation finds the start, tracking follows the truth; the outputs are those of an
// offline --localize run, the streams are gone, and the map folder is untouched.
TEST_F(LiveSickSavedMap, LocalisesLiveScansOnASavedMap)
{
	const size_t first = m_rec.scans.size() / 2;
	CLms1xxEmulator emu(scansFrom(first));
	const auto d = prepareLiveRun("live_localize", emu, m_rec.sensorPose, "");
	const auto mapBefore = fs::last_write_time(m_dir + "/sena/map.simplemap.gz");
	ASSERT_EQ(runUntilServed(d, emu, {"--localize", m_dir + "/sena"}), 0);

	const std::string stats = readTextFile(d.out + "/stats.json");
	EXPECT_NE(stats.find("\"mode\": \"localize\""), std::string::npos) << stats;
	EXPECT_NE(stats.find("\"status\": \"stopped on request\""), std::string::npos) << stats;
	const long received = jsonInt(readTextFile(d.out + "/live.json"), "scans", "\"received\"");
	const long scans = jsonInt(stats, "scans"), localized = jsonInt(stats, "localized_scans");
	EXPECT_GE(received, static_cast<long>(0.9 * emu.scansServed()));
	EXPECT_EQ(scans, received);
	EXPECT_GE(localized, static_cast<long>(0.9 * scans)) << stats;
	EXPECT_GE(jsonInt(stats, "attempts", "global_localization"), 1) << stats;
	const TRows live = readTum(d.out + "/trajectory.tum");
	ASSERT_EQ(static_cast<long>(live.size()), localized);
	// timing.csv: a header and one row per scan.
	const std::string timing = readTextFile(d.out + "/timing.csv");
	EXPECT_EQ(static_cast<long>(std::count(timing.begin(), timing.end(), '\n')), scans + 1);
	EXPECT_TRUE(fs::exists(d.out + "/config.ini"));
	EXPECT_FALSE(fs::exists(d.out + "/.trajectory.tum.stream"));
	EXPECT_FALSE(fs::exists(d.out + "/.timing.csv.stream"));
	EXPECT_EQ(fs::last_write_time(m_dir + "/sena/map.simplemap.gz"), mapBefore);

	// The localised scans are the last ones received; paired by index only where every scan
	// served arrived (one run on a loaded machine lost the last of 112: the index pairing put
	// each pose one scan off, 0.3-0.97 m; 56 of 56 within 0.1 m of the nearest truth pose).
	const size_t tail = live.size();
	expectLocated(
		poseErrors(live, m_truth, first + emu.scansServed() - tail, emu.scansServed()));
}

// --initial-map: a map of SENA's first 60 % is continued with live scans from 40 % to the
// end: the start is found in it, the map grows, and the new scans lie on the truth.
TEST_F(LiveSickSavedMap, ContinuesASavedMapWithLiveScans)
{
	writeSenaPrefix(m_dir + "/prefix.rawlog", m_rec.scans.size() * 6 / 10);
	auto r = runProcess(binaryPath("lrgc-slam"), {"--input", m_dir + "/prefix.rawlog", "--out",
												  m_dir + "/prefix", "-q"});
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const long oldKeyframes = jsonInt(readTextFile(m_dir + "/prefix/stats.json"), "keyframes");
	const size_t first = m_rec.scans.size() * 4 / 10;
	CLms1xxEmulator emu(scansFrom(first));
	const auto d = prepareLiveRun("live_initial_map", emu, m_rec.sensorPose, "");
	ASSERT_EQ(runUntilServed(d, emu, {"--initial-map", m_dir + "/prefix"}), 0);

	const std::string stats = readTextFile(d.out + "/stats.json");
	const long keyframes = jsonInt(stats, "keyframes"), scans = jsonInt(stats, "scans");
	EXPECT_GT(keyframes, oldKeyframes) << "the map did not grow\n" << stats;
	EXPECT_NE(stats.find(m_dir + "/prefix"), std::string::npos) << stats;
	mrpt::maps::CSimpleMap simplemap;
	{
		mrpt::io::CFileGZInputStream f(d.out + "/map.simplemap.gz");
		auto arch = mrpt::serialization::archiveFrom(f);
		arch >> simplemap;
	}
	EXPECT_EQ(static_cast<long>(simplemap.size()), keyframes);
	mrpt::graphs::CNetworkOfPoses2DInf graph;
	graph.loadFromTextFile(d.out + "/graph.graph");
	EXPECT_EQ(static_cast<long>(graph.nodes.size()), keyframes);
	const TRows live = readTum(d.out + "/trajectory.tum");
	ASSERT_EQ(static_cast<long>(live.size()), scans);
	// Paired by index only where every scan served arrived: a scan lost on the way (15 of 135
	// in one run on a loaded machine) shifts the index pairing by the scans lost.
	expectLocated(poseErrors(live, m_truth, first, emu.scansServed()));
	GTEST_LOG_(INFO) << "keyframes " << oldKeyframes << " -> " << keyframes;
}

// The first signal cuts the computation in hand short in a live run too (issue 30's stop
// token, now given to live mode, 3 s after the signal: DelayedStop.h). The computation: a scan
// match that does not converge ([ScanMatcher] max_iterations = 1e9, as in SlamSignals), here
// in the probe that looks for the start (on scans of SENA seen in a mirror, which fit nowhere
// in its map). Without the token the run never got back to its stop: still running two
// minutes after the signal.
TEST_F(LiveSickSavedMap, SigtermDuringANonConvergingMatchStopsIt)
{
	std::vector<TLms1xxScan> mirrored;
	for (int lap = 0; lap < 10; ++lap)  // about a minute of scans: still flowing at the signal
		for (auto s : m_rec.scans)
		{
			std::reverse(s.distancesMm.begin(), s.distancesMm.end());  // y -> -y
			mirrored.push_back(std::move(s));
		}
	CLms1xxEmulator emu(mirrored);
	const auto d = prepareLiveRun("live_endless_match", emu, m_rec.sensorPose,
								  "[ScanMatcher]\nmax_iterations = 1000000000\n");
	CChildProcess app(binaryPath("lrgc-slam"),
					  {"--live", d.sensors, "--config", d.config, "--out", d.out, "--localize",
					   m_dir + "/sena"},
					  d.dir + "/live.log");
	ASSERT_TRUE(waitUntil([&] { return emu.scansServed() >= 500; }, kLiveStartupBound + 60))
		<< app.output();
	ASSERT_FALSE(emu.finished());
	const auto t0 = std::chrono::steady_clock::now();
	app.signal(SIGTERM);
	const auto rc = app.waitExit(120);
	const double seconds =
		std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
	ASSERT_TRUE(rc.has_value()) << app.output();
	EXPECT_EQ(*rc, 1) << "no start can be found: exit status 1\n" << app.output();
	// The match in hand is cut 3 s after the signal, and each queued scan's match at once;
	// then the driver is joined (its current call: tens of ms). The bound leaves room for a
	// loaded machine.
	EXPECT_LT(seconds, 15.0) << "the match in hand ran on after the signal\n" << app.output();
	const std::string stats = readTextFile(d.out + "/stats.json");
	EXPECT_NE(stats.find("no start found in the map"), std::string::npos) << stats;
}
