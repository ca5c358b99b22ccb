/* A large loop (paper: "large cyclic environments"): 320 m around a 100 m x 50 m block of 2.4 m
 * corridors (with doors into side rooms, and boxes) whose corners are 20 m halls, seen with a
 * 6 m laser. In the middle of a hall the laser sees nothing, so each 90-degree turn is
 * dead-reckoned, with a gyro-like bias of the odometry on turns (8 % too much): the heading
 * drifts by about 7 degrees per corner, over 20 degrees by the time the robot is back on its
 * first corridor, and the position there is off by metres. The robot then drives 55 m along
 * that corridor, as a robot back on known ground does. With loop closing on, the loop closer
 * must find the start again (the search window set by the propagated covariance), close the
 * loop with true links only, and end near the truth. */
#include <gtest/gtest.h>
#include <lrgc/common/se2.h>
#include <lrgc_apps/eval/loop_recall.h>

#include <chrono>
#include <cmath>
#include <iostream>
#include <limits>
#include <random>

#include "synthetic_run.h"

using namespace lrgc::test;
using lrgc::CMetricMapBuilderLRGC;
using lrgc::TLRGCParams;

namespace
{
/** The loop's corners (0,0), (L,0), (L,H), (0,H) [m] and how far along the first corridor the
 * run ends [m]. */
struct TLoopShape
{
	double L = 100, H = 50;
	double returnTo = 75;
};
constexpr double kLoopCorridor = 2.4;  // [m] corridor width
constexpr double kHall = 10;           // [m] half side of the corner halls
constexpr double kTurnBias = 1.08;     // odometry turn / true turn
constexpr double kDoor = 1.0;          // [m] width of a door into a side room
constexpr double kLoopRoom = 3.0;      // [m] width of a side room along the corridor
constexpr double kRoomSpacing = 6.0;   // [m] least distance between two doors on one side

/** A wall from a to b (axis-aligned) with a doorway of width `door` centred at `door_at`
 * (a point on the wall), or no doorway if door <= 0. */
void wallWithDoor(CSyntheticWorld& w, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
				  const Eigen::Vector2d& doorAt, double door)
{
	if (door <= 0)
	{
		w.addSegment(a, b);
		return;
	}
	const Eigen::Vector2d u = (b - a).normalized();
	w.addSegment(a, doorAt - 0.5 * door * u);
	w.addSegment(doorAt + 0.5 * door * u, b);
}

CSyntheticWorld makeHallLoopWorld(uint32_t seed, const TLoopShape& shape)
{
	CSyntheticWorld w;
	const double L = shape.L, height = shape.H;
	const std::vector<Eigen::Vector2d> corners{{0, 0}, {L, 0}, {L, height}, {0, height}};
	// Halls: square, doorways where the corridors to the neighbouring corners enter.
	for (size_t i = 0; i < 4; ++i)
	{
		const Eigen::Vector2d c = corners[i];
		const Eigen::Vector2d toNext = (corners[(i + 1) % 4] - c).normalized();
		const Eigen::Vector2d toPrev = (corners[(i + 3) % 4] - c).normalized();
		const Eigen::Vector2d sx(kHall, 0), sy(0, kHall);
		const Eigen::Vector2d p00 = c - sx - sy, p10 = c + sx - sy, p11 = c + sx + sy,
							  p01 = c - sx + sy;
		auto door = [&](const Eigen::Vector2d& dir)
		{ return (dir == toNext || dir == toPrev) ? kLoopCorridor : 0.0; };
		wallWithDoor(w, p00, p10, c - sy, door({0, -1}));
		wallWithDoor(w, p10, p11, c + sx, door({1, 0}));
		wallWithDoor(w, p11, p01, c + sy, door({0, 1}));
		wallWithDoor(w, p01, p00, c - sx, door({-1, 0}));
	}
	// Corridors between the halls' doorways. Their walls have doors into side rooms now and
	// then, and boxes against them, as real corridors do: plain walls would make any place
	// along a corridor look like any other, and the ambiguity filter rightly refuses those.
	std::mt19937 rng(seed);
	std::uniform_real_distribution<double> u(0, 1);
	for (size_t i = 0; i < 4; ++i)
	{
		const Eigen::Vector2d a = corners[i], b = corners[(i + 1) % 4];
		const Eigen::Vector2d d = (b - a).normalized(), n(-d.y(), d.x());
		const Eigen::Vector2d s = a + kHall * d, e = b - kHall * d;
		const double len = (e - s).norm();
		for (const double side : {-1.0, 1.0})
		{
			const Eigen::Vector2d wall =
				0.5 * kLoopCorridor * side * n;  // corridor axis -> wall
			double from = 0;  // along the corridor [m], where the current wall piece starts
			for (double t = 3 + 8 * u(rng); t < len - 3; t += kRoomSpacing + 8 * u(rng))
			{
				const double depth = 2.5 + 1.5 * u(rng);
				const Eigen::Vector2d out = side * depth * n;
				const Eigen::Vector2d d0 = s + (t - 0.5 * kDoor) * d + wall;
				const Eigen::Vector2d d1 = s + (t + 0.5 * kDoor) * d + wall;
				const Eigen::Vector2d r0 = s + (t - 0.5 * kLoopRoom) * d + wall;
				const Eigen::Vector2d r1 = s + (t + 0.5 * kLoopRoom) * d + wall;
				w.addSegment(s + from * d + wall, d0);
				const std::vector<Eigen::Vector2d> room{d0, r0, r0 + out, r1 + out, r1, d1};
				for (size_t k = 0; k + 1 < room.size(); ++k) w.addSegment(room[k], room[k + 1]);
				from = t + 0.5 * kDoor;
			}
			w.addSegment(s + from * d + wall, e + wall);
		}
		for (double t = 3 + 6 * u(rng); t < len - 2; t += 4 + 8 * u(rng))
		{
			const double side = u(rng) < 0.5 ? -1.0 : 1.0;
			w.addBox(s + t * d + side * (0.5 * kLoopCorridor - 0.15) * n, 0.15, 0.15);
		}
	}
	return w;
}

/** Once around from (20, 0) and on along the first corridor to (shape.returnTo, 0), or,
 * without `returns`, around three sides only, ending at (0, 5) before any revisit; odometry
 * turns `turnBias` times the true turn (a gyro scale error) on top of the usual noise (drawn
 * from `noiseSeed`). */
TTrajectory hallLoop(double turnBias, uint32_t noiseSeed, bool returns, const TLoopShape& shape)
{
	const double L = shape.L, height = shape.H;
	std::vector<Eigen::Vector2d> around{{20, 0}, {L, 0}, {L, height}, {0, height}};
	if (returns)
		around.insert(around.end(), {{0, 0}, {shape.returnTo, 0}});
	else
		around.emplace_back(0, 5);
	TTrajectory tr = makeTrajectory(around, 0.2, TOdometryNoise{}, noiseSeed);
	for (auto& inc : tr.odometryIncrements) inc.phi *= turnBias;
	rebuildOdometryPoses(tr);
	return tr;
}

struct TLargeLoopRun
{
	TTrajectoryError error;
	double headingErrorAtReturn = 0;  //!< [rad] when first back at the start (x = 20 m, y = 0)
	double offAtReturn = 0;           //!< [m] position error there (relative to the first pose)
	lrgc::TMapBuilderStats stats;
	lrgc::TLoopCloserStats loopStats;
	TLoopLinkAudit links;
};

/** How the loop closer is set up for a run; defaults otherwise. */
struct TLoopSetup
{
	bool loopClosing = true;
	double maxWindowXY = -1, maxWindowTheta = -1;  //!< [m], [rad]; < 0: the default caps
	double confirmAboveSigma = -1;                 //!< [m]; < 0: the default
	double maxBacklog =
		-1;  //!< [LoopCloser] max_backlog_keyframes [keyframes]; < 0: the default
	double patchMaxTravel = -1;  //!< [LoopCloser] patch_max_travel_m [m]; < 0: the default
	size_t farSearchEvery = 0;   //!< [LoopCloser] far_search_every_keyframes; 0: the default
	double workerBudget = -1;    //!< [LoopCloser] worker_budget_ms [ms]; < 0: the default
	/** The gate of single links with no drift term and no patch growth for ambiguity (the
	 * defaults before gate14: gate_fuse_links false, gate_drift_xy_m2_per_m 0,
	 * patch_keyframes_per_ambiguity 0), whose std is tens of metres at the return. */
	bool singleLinkGate = false;
	double turnBias = kTurnBias;  //!< odometry turn / true turn
	uint32_t worldSeed = 17;      //!< side rooms and boxes
	uint32_t noiseSeed = 3;       //!< odometry noise
	bool returns = true;          //!< hallLoop(): back along the first corridor, or not
	TLoopShape shape;             //!< the loop's size
};

TLargeLoopRun runHallLoop(const TLoopSetup& setup)
{
	const auto world = makeHallLoopWorld(setup.worldSeed, setup.shape);
	const TTrajectory tr =
		hallLoop(setup.turnBias, setup.noiseSeed, setup.returns, setup.shape);
	EXPECT_GT(minClearance(world, tr.truePoses), 0.5);
	TSyntheticRunOptions opt;
	opt.laser.maxRange = 6;
	TLRGCParams p;
	p.builder.loop_closing = setup.loopClosing;
	if (setup.maxWindowXY >= 0) p.loop.max_window_xy_m = setup.maxWindowXY;
	if (setup.maxWindowTheta >= 0) p.loop.max_window_phi = setup.maxWindowTheta;
	if (setup.confirmAboveSigma >= 0) p.loop.confirm_above_sigma_m = setup.confirmAboveSigma;
	if (setup.maxBacklog >= 0)
		p.loop.max_backlog_keyframes = static_cast<size_t>(setup.maxBacklog);
	if (setup.patchMaxTravel >= 0) p.loop.patch_max_travel_m = setup.patchMaxTravel;
	if (setup.farSearchEvery > 0) p.loop.far_search_every_keyframes = setup.farSearchEvery;
	if (setup.workerBudget >= 0) p.loop.worker_budget_ms = setup.workerBudget;
	if (setup.singleLinkGate)
	{
		p.loop.gate_fuse_links = false;
		p.loop.gate_drift_xy_m2_per_m = 0;
		p.loop.patch_keyframes_per_ambiguity = 0;
	}
	CMetricMapBuilderLRGC builder(p);
	builder.setMinLoggingLevel(mrpt::system::LVL_ERROR);  // every hall scan is skipped
	feedBuilder(builder, world, tr, opt);
	TLargeLoopRun run;
	run.stats = builder.stats();
	run.loopStats = builder.loopCloserStats();
	// Scans from the middle of a hall saw nothing and were skipped: compare the others, each
	// with the true pose of its step (feedBuilder stamps step k at 1.6e9 + k * scanPeriod).
	const auto est = builder.trajectory();
	std::vector<size_t> step;
	std::vector<mrpt::math::TPose2D> truth;
	for (const auto& e : est)
	{
		step.push_back(static_cast<size_t>(
			std::lround((mrpt::Clock::toDouble(e.timestamp) - 1.6e9) / opt.scanPeriod)));
		truth.push_back(tr.truePoses.at(step.back()));
	}
	run.error = trajectoryError(est, truth);
	// The first pose back on the first corridor past the start, after the whole loop.
	for (size_t i = est.size() / 2; i < est.size(); ++i)
		if (std::abs(truth[i].y) < 0.1 && truth[i].x >= 20 && truth[i].x < 30)
		{
			const double trueTurn = lrgc::between(truth.front(), truth[i]).phi;
			const double estTurn = lrgc::between(est.front().robotInMap, est[i].robotInMap).phi;
			run.headingErrorAtReturn = std::abs(mrpt::math::wrapToPi(estTurn - trueTurn));
			const auto estRel = lrgc::between(est.front().robotInMap, est[i].robotInMap);
			const auto trueRel = lrgc::between(truth.front(), truth[i]);
			run.offAtReturn = std::hypot(estRel.x - trueRel.x, estRel.y - trueRel.y);
			break;
		}
	run.links = auditLoopLinks(builder, truth, 0.3, 5 * M_PI / 180);
	if (setup.loopClosing)  // the kept loop links' calibration (lrgc_apps/eval/loop_recall.h)
	{
		std::vector<lrgc::apps::eval::TRecallKeyframe> kfs;
		for (const auto& kf : builder.keyframes())
			kfs.push_back({opt.scanPeriod * double(kf.scanIndex), truth.at(kf.scanIndex)});
		std::printf("  %s", lrgc::apps::eval::calibrationReport(
								lrgc::apps::eval::evaluateLoopRecall(builder.graph(), kfs))
								.c_str());
	}
	return run;
}

/** The run without loop closing (the same for every test). */
const TLargeLoopRun& drifted()
{
	static const TLargeLoopRun run = []
	{
		TLoopSetup s;
		s.loopClosing = false;
		return runHallLoop(s);
	}();
	return run;
}

void expectClosedCorrectly(const TLargeLoopRun& on)
{
	const TLargeLoopRun& off = drifted();
	::testing::Test::RecordProperty("heading_drift_deg",
									std::to_string(mrpt::RAD2DEG(off.headingErrorAtReturn)));
	::testing::Test::RecordProperty("final_off_m", std::to_string(off.error.finalXY));
	EXPECT_GT(mrpt::RAD2DEG(off.headingErrorAtReturn), 20.0) << "the loop must drift enough";
	EXPECT_GT(off.error.finalXY, 3.0);
	::testing::Test::RecordProperty("final_on_m", std::to_string(on.error.finalXY));
	::testing::Test::RecordProperty("rms_on_m", std::to_string(on.error.rmsXY));
	EXPECT_GT(on.stats.loopClosures, 0U);
	EXPECT_GT(on.links.enabledTrue, 0U);
	EXPECT_EQ(on.links.enabledFalse, 0U) << on.links.firstEnabledFalse;
	EXPECT_LT(on.error.finalXY, 0.5) << "drifted run: " << off.error.finalXY << " m";
	EXPECT_LT(mrpt::RAD2DEG(on.headingErrorAtReturn), 2.0);
}
}  // namespace

// The defaults: the window from the covariance, capped at 15 m / 30 deg.
TEST(LargeLoop, threeHundredMetresWithTwentyDegreesOfHeadingDriftIsClosed)
{
	expectClosedCorrectly(runHallLoop({}));
}

// A search window as large as the covariance says (here +-197 m and the whole heading circle
// at the return, 65 m / 61 deg std): branch and bound over the old map's extent and blocks of
// headings, and the three filters.
TEST(LargeLoop, closedWithTheWindowTheCovarianceAsksFor)
{
	TLoopSetup s;
	s.maxWindowXY = 1000, s.maxWindowTheta = M_PI;
	// Searches over the whole hall cost the worker seconds each: with the default backlog
	// ([LoopCloser] max_backlog_keyframes, 150 keyframes) its modelled schedule skips the
	// searches of the return, the ones that close the loop. A user who uncaps the window lets
	// the worker fall further behind.
	s.maxBacklog = 100000;
	expectClosedCorrectly(runHallLoop(s));
}

// A wide window holds look-alikes: at 30 m / 60 deg, before the robot is back, a patch of the
// last corridor matches another place (score 0.77, no rival in that window) and, with the
// gate's 41 m std, the back-end cannot refuse it (46 m final error). Held until a later,
// independent match agrees, it is dropped; the true loop, matched again and again on the
// way along the first corridor, is confirmed and closed. The look-alike needs the patch of 40
// keyframes the gate's std asks for: capped at patch_max_travel_m (24 m) it is not there, so
// the cap is lifted to show the hold. The gate is the single-link one (41 m std at the return):
// the calibrated default's window there (fused links, the drift term) no longer holds the
// look-alike (measured, gate13 and gate14: no false link kept even without the hold), so the
// hold has nothing to drop there.
// It still matters wherever a window is tens of metres wide (a long first return).
TEST(LargeLoop, aLookAlikeInAWideWindowIsHeldAndDropped)
{
	TLoopSetup s;
	s.singleLinkGate = true;
	s.maxWindowXY = 30, s.maxWindowTheta = mrpt::DEG2RAD(60.0);
	s.patchMaxTravel = 0;
	s.confirmAboveSigma = 0;
	const TLargeLoopRun unconfirmed = runHallLoop(s);
	EXPECT_GT(unconfirmed.links.enabledFalse, 0U) << "the look-alike must be there to refuse";
	s.confirmAboveSigma = 5;
	const TLargeLoopRun confirmed = runHallLoop(s);
	EXPECT_GE(confirmed.loopStats.unconfirmed, 1U);
	expectClosedCorrectly(confirmed);
}

/** The hall loop with odometry turning `turnBias` times too much, without and with loop
 * closing: the drift must be tens of metres, and no false loop link may be kept. */
std::pair<TLargeLoopRun, TLargeLoopRun> farRun(TLoopSetup s)
{
	TLoopSetup off = s;
	off.loopClosing = false;
	const TLargeLoopRun drifted = runHallLoop(off);
	EXPECT_GT(drifted.error.finalXY, 20.0) << "the loop must drift by tens of metres";
	const TLargeLoopRun on = runHallLoop(s);
	const auto& l = on.loopStats;
	std::cout << "turn bias " << s.turnBias << ", noise seed " << s.noiseSeed << ": drifted "
			  << drifted.error.finalXY << " m (" << mrpt::RAD2DEG(drifted.headingErrorAtReturn)
			  << " deg, " << drifted.offAtReturn << " m off at the return); with loop closing "
			  << on.error.finalXY << " m, closures " << on.stats.loopClosures
			  << ", far searches " << l.farSearches << " (waited " << l.farSearchesWaited
			  << "; rings " << l.farRings << "), candidates " << l.farCandidates
			  << ", confirmed " << l.farConfirmed << ", rejected " << l.farRejected
			  << ", closed " << l.farClosures << ", shed " << l.searchesShed << " (keyframes "
			  << (l.shedKeyframes.empty() ? 0 : l.shedKeyframes.front()) << "-"
			  << (l.shedKeyframes.empty() ? 0 : l.shedKeyframes.back()) << ", "
			  << l.droppedKeyframes.size() << " dropped); far searches merged "
			  << l.farSearchesMerged << " (places " << l.farPlacesMerged << "), dropped "
			  << l.farDroppedKeyframes.size() << ", closed out " << l.farSearchesClosedOut
			  << "\n";
	EXPECT_EQ(on.links.enabledFalse, 0U) << on.links.firstEnabledFalse;
	return {drifted, on};
}

// Drift of tens of metres at the return (issue 28): odometry turns 25 % too much, so the
// heading is off by 87 degrees when the robot is back and the start lies 30 m from where the
// map has it, far outside the capped window (15 m / 30 deg). With time for it (no modelled
// worker: worker_budget_ms 0), the far search over the whole old map proposes the true place
// among its distinct peaks, a later patch confirms it and the loop closes with true links.
TEST(LargeLoop, tensOfMetresOfDriftAreClosedByTheFarSearchWithTime)
{
	TLoopSetup s;
	s.turnBias = 1.25;
	s.farSearchEvery = 25;
	s.workerBudget = 0;
	const auto [drifted, on] = farRun(s);
	EXPECT_GE(on.loopStats.farClosures, 1U);
	EXPECT_LT(on.error.finalXY, 0.5) << "drifted run: " << drifted.error.finalXY << " m";
}

// The same with the defaults (far_search_every_keyframes 25): the far search runs on a lane of
// its own, a second modelled worker with the near worker's budget (5 ms per keyframe), never in
// the near searches' schedule. One search costs about 80 ms of modelled work here (the places
// in one pass over the old path, eight checks in a 1 m / 5 deg window, one step per check), so
// the one that starts after the return finishes within a few keyframes and a later patch
// confirms its place: the loop closes with true links only.
TEST(LargeLoop, tensOfMetresOfDriftAreClosedWithTheDefaults)
{
	TLoopSetup s;
	s.turnBias = 1.25;
	const auto [drifted, on] = farRun(s);
	EXPECT_GE(on.loopStats.farClosures, 1U);
	EXPECT_LT(on.error.finalXY, 0.5) << "drifted run: " << drifted.error.finalXY << " m";
	EXPECT_TRUE(on.loopStats.droppedKeyframes.empty()) << "a deferred search was dropped";
}

// Where the far search closes nothing it moves nothing: the same drift, no return (three
// sides), the defaults. Its searches run and propose look-alikes, but on their own lane (their
// work counted apart, their steps on their own thread, taken back at points fixed by the
// modelled schedule), so the map is the one without them, to the bit.
TEST(LargeLoop, theFarSearchMovesNoMapWhereItClosesNothing)
{
	TLoopSetup s;
	s.turnBias = 1.25;
	s.returns = false;
	const TLargeLoopRun on = runHallLoop(s);
	s.farSearchEvery = std::numeric_limits<size_t>::max();  // never due: off
	const TLargeLoopRun off = runHallLoop(s);
	EXPECT_GE(on.loopStats.farSearches, 3U) << "the far search must run";
	EXPECT_EQ(on.loopStats.farClosures, 0U);
	EXPECT_EQ(off.loopStats.farSearches, 0U);
	EXPECT_EQ(on.error.rmsXY, off.error.rmsXY);
	EXPECT_EQ(on.error.finalXY, off.error.finalXY);
	EXPECT_EQ(on.stats.loopClosures, off.stats.loopClosures);
	EXPECT_EQ(on.loopStats.work.referenceMs(), off.loopStats.work.referenceMs());
}

// Look-alikes only: the same drift, but the run ends before the robot is back (three sides,
// no place revisited). With time for it the far search runs as above and its places are
// corridor look-alikes; some pass the full-resolution check and are held, but no later patch
// confirms exactly one, so no loop link may be kept.
TEST(LargeLoop, theFarSearchAcceptsNoLookAlikeWhereNothingIsRevisited)
{
	TLoopSetup s;
	s.turnBias = 1.25;
	s.farSearchEvery = 25;
	s.workerBudget = 0;
	s.returns = false;
	const TLargeLoopRun on = runHallLoop(s);
	const auto& l = on.loopStats;
	std::cout << "no return: far searches " << l.farSearches << ", candidates "
			  << l.farCandidates << ", confirmed " << l.farConfirmed << ", held "
			  << l.heldForConfirmation << ", closed " << l.farClosures << "\n";
	EXPECT_GE(l.farSearches, 3U) << "the far search must run";
	EXPECT_GE(l.farCandidates, 8U);
	EXPECT_EQ(l.farClosures, 0U);
	EXPECT_EQ(on.stats.loopClosures, 0U);
	EXPECT_EQ(on.links.enabledFalse, 0U) << on.links.firstEnabledFalse;
}

// A return more than 100 m off (issue 28 item 1: the held-out long-range log revisits places a
// median 126 m, at least 82 m, from where the map has them). The hall loop at twice the size:
// 600 m around a 200 x 100 m block, the same corridors, halls, 6 m laser and odometry turning
// 25 % too much, so the start lies 117 m (93 deg) from where the map has it at the return; the
// run goes on only 55 m along the first corridor. The far search's window is window_sigmas
// sigma of the gate (beyond far_window_xy_m, cut at the old map's extent), its places proposed
// ring by ring and checked best first over all rings (coarse to fine), a search still checking
// when the next is due merged into it, not dropped: with the defaults (the modelled worker) it
// finishes within those 55 m and the loop closes with true links only (main at 37911f0 needed
// 115 m of return, or worker_budget_ms 0).
TEST(LargeLoop, aReturnMoreThan100mOffClosesWithin55m)
{
	TLoopSetup s;
	s.turnBias = 1.25;
	s.shape = {200, 100, 75};
	const auto [drifted, on] = farRun(s);
	EXPECT_GT(drifted.offAtReturn, 100.0);
	EXPECT_TRUE(on.loopStats.farDroppedKeyframes.empty()) << "a far search was dropped";
	EXPECT_GT(on.loopStats.farRings, on.loopStats.farSearches) << "no window beyond 100 m";
	EXPECT_GE(on.loopStats.farClosures, 1U);
	EXPECT_LT(on.error.finalXY, 0.5) << "drifted run: " << drifted.error.finalXY << " m";
}

// The same large loop without the return (three sides, nothing revisited), the defaults: the
// far search runs over windows beyond far_window_xy_m and proposes look-alikes in every ring,
// but no later patch confirms exactly one, so no loop link may be kept.
TEST(LargeLoop, aLoopMoreThan100mOffAcceptsNoLookAlike)
{
	TLoopSetup s;
	s.turnBias = 1.25;
	s.shape = {200, 100, 135};
	s.returns = false;
	const TLargeLoopRun on = runHallLoop(s);
	const auto& l = on.loopStats;
	std::cout << "no return: far searches " << l.farSearches << " (rings " << l.farRings
			  << "), candidates " << l.farCandidates << ", confirmed " << l.farConfirmed
			  << ", held " << l.heldForConfirmation << ", closed " << l.farClosures << "\n";
	EXPECT_GE(l.farSearches, 3U) << "the far search must run";
	EXPECT_GT(l.farRings, l.farSearches) << "its windows must reach beyond far_window_xy_m";
	EXPECT_EQ(l.farClosures, 0U);
	EXPECT_EQ(on.stats.loopClosures, 0U);
	EXPECT_EQ(on.links.enabledFalse, 0U) << on.links.firstEnabledFalse;
}
