/* Loop closing in the background (issue 12): the ring of tests/loop_closing_test.cpp (20 m x
 * 14 m of corridors, 9 % wheel slip on the north corridor, closed by loop closing), mapped
 *  - offline with a worker slowed on purpose (every loop search first sleeps), with the
 *    normal worker, and with no thread at all: the three trajectories must be identical, the
 *    slowed run must have waited for results (so the slow path was taken), and the loop must
 *    be closed;
 *  - live (results applied as soon as ready) with a very slow worker: the mapping thread must
 *    never wait for it;
 *  - while another thread keeps reading the map through the getters MRPT users call
 *    (getCurrentPoseEstimation, getCurrentlyBuiltMap, getCurrentlyBuiltMetricMap, trajectory):
 *    every copy must be whole, and the map the same as without the reader. */
#include <lrgc/loop_closing/LoopWork.h>
#include <lrgc/map_builder/TestAccess.h>
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CObservationOdometry.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <thread>

#include "synthetic_run.h"

using namespace lrgc::test;
using lrgc::CMetricMapBuilderLRGC;
using lrgc::TLRGCParams;

namespace
{
constexpr double kWorkerRingW = 20, kWorkerRingH = 14;  // [m] ring size

TTrajectory workerSlippingRing()
{
	TTrajectory tr = makeTrajectory({{4, 1},
									 {kWorkerRingW - 1, 1},
									 {kWorkerRingW - 1, kWorkerRingH - 1},
									 {1, kWorkerRingH - 1},
									 {1, 1},
									 {kWorkerRingW - 1, 1},
									 {kWorkerRingW - 1, 6}},
									0.2, TOdometryNoise{}, 11);
	for (size_t k = 0; k < tr.odometryIncrements.size(); ++k)
		if (tr.truePoses[k].y > kWorkerRingH - 2)
		{
			tr.odometryIncrements[k].x *= 1.09;
			tr.odometryIncrements[k].y *= 1.09;
		}
	rebuildOdometryPoses(tr);
	return tr;
}

struct TWorkerRun
{
	lrgc::TTrajectory trajectory;
	lrgc::TMapBuilderStats stats;
	TTrajectoryError error;
	lrgc::TLoopCloserStats loop;
};

TWorkerRun mapRing(
	const TLRGCParams& p, std::chrono::milliseconds extraDelay,
	const std::function<void(const CMetricMapBuilderLRGC&, std::atomic<bool>&)>& reader = {},
	double scanPeriod = 0.2)
{
	const auto world = makeRingCorridorWorld(kWorkerRingW, kWorkerRingH, 2.0, 5, 4);
	const TTrajectory tr = workerSlippingRing();
	TSyntheticRunOptions opt;
	opt.laser.maxRange = 6;
	opt.scanPeriod = scanPeriod;
	CMetricMapBuilderLRGC builder(p);
	lrgc::TLoopClosingTestAccess::setExtraDelay(builder, extraDelay);
	std::atomic<bool> done{false};
	std::thread readerThread;
	if (reader) readerThread = std::thread([&] { reader(builder, done); });
	feedBuilder(builder, world, tr, opt);
	done = true;
	if (readerThread.joinable()) readerThread.join();
	return {builder.trajectory(), builder.stats(),
			trajectoryError(builder.trajectory(), tr.truePoses), builder.loopCloserStats()};
}

void expectSameWorkerTrajectory(const lrgc::TTrajectory& a, const lrgc::TTrajectory& b,
								const char* what)
{
	ASSERT_EQ(a.size(), b.size()) << what;
	for (size_t i = 0; i < a.size(); ++i)
	{
		ASSERT_EQ(a[i].robotInMap.x, b[i].robotInMap.x) << what << ", scan " << i;
		ASSERT_EQ(a[i].robotInMap.y, b[i].robotInMap.y) << what << ", scan " << i;
		ASSERT_EQ(a[i].robotInMap.phi, b[i].robotInMap.phi) << what << ", scan " << i;
	}
}
}  // namespace

TEST(LoopClosingWorker, offlineResultsDoNotDependOnTheWorkersSpeed)
{
	TLRGCParams p;
	p.loop.result_delay_keyframes = 2;
	const TWorkerRun normal = mapRing(p, std::chrono::milliseconds(0));
	const TWorkerRun slow = mapRing(p, std::chrono::milliseconds(15));
	p.loop.background = false;
	const TWorkerRun inlineRun = mapRing(p, std::chrono::milliseconds(0));

	EXPECT_GT(normal.stats.loopClosures, 0U);
	EXPECT_LT(normal.error.finalXY, 0.3);
	// The slowed worker was not done when its results were due: the mapping thread waited.
	EXPECT_GT(slow.stats.loopResultWaits, 0U);
	EXPECT_EQ(inlineRun.stats.loopResultWaits, 0U);
	expectSameWorkerTrajectory(normal.trajectory, slow.trajectory, "slowed worker");
	expectSameWorkerTrajectory(normal.trajectory, inlineRun.trajectory, "no worker thread");
	EXPECT_EQ(normal.stats.loopClosureLinks, slow.stats.loopClosureLinks);
	EXPECT_EQ(normal.stats.loopClosureLinks, inlineRun.stats.loopClosureLinks);
}

TEST(LoopClosingWorker, aSlowWorkerNeverStallsTheMappingThreadInLiveMode)
{
	TLRGCParams p;
	p.loop.apply_when_ready = true;
	const TWorkerRun live = mapRing(p, std::chrono::milliseconds(50));
	EXPECT_EQ(live.stats.loopResultWaits, 0U);
	EXPECT_EQ(live.stats.scans, workerSlippingRing().truePoses.size());
}

TEST(MapBuilderThreads, gettersAreSafeWhileMapping)
{
	const TLRGCParams p;
	size_t reads = 0, inconsistent = 0;
	auto reader = [&](const CMetricMapBuilderLRGC& b, std::atomic<bool>& done)
	{
		auto& builder = const_cast<CMetricMapBuilderLRGC&>(b);
		size_t lastScans = 0;
		while (!done)
		{
			const auto pose = builder.getCurrentPoseEstimation()->getMeanVal();
			mrpt::maps::CSimpleMap keyframes;
			builder.getCurrentlyBuiltMap(keyframes);
			const auto trajectory = builder.trajectory();
			const auto* grid = builder.getCurrentlyBuiltMetricMap();
			const size_t scans = builder.statsCopy().scans;
			// Copies are whole: finite poses, every keyframe with its observations, and the
			// trajectory never shrinks.
			if (!std::isfinite(pose.x()) || !std::isfinite(pose.yaw())) ++inconsistent;
			for (size_t i = 0; i < keyframes.size(); ++i)
				if (const auto [pdf, sf] = keyframes.get(i); !pdf || !sf || sf->size() == 0)
					++inconsistent;
			if (trajectory.size() < lastScans || grid == nullptr || grid->maps.empty())
				++inconsistent;
			lastScans = std::max(lastScans, std::min(scans, trajectory.size()));
			++reads;
		}
	};
	const TWorkerRun alone = mapRing(p, std::chrono::milliseconds(0));
	const TWorkerRun read = mapRing(p, std::chrono::milliseconds(0), reader);
	EXPECT_GT(reads, 10U);
	EXPECT_EQ(inconsistent, 0U);
	expectSameWorkerTrajectory(alone.trajectory, read.trajectory, "with a reader thread");
}

namespace
{
/** Exposes MRPT's critical section of the builder, to hold it from the test. */
struct CLockableBuilder : public CMetricMapBuilderLRGC
{
	using CMetricMapBuilderLRGC::enterCriticalSection;
	using CMetricMapBuilderLRGC::leaveCriticalSection;
};
}  // namespace

// Each getter and each map change takes MRPT's critical section: while the test holds it, a
// call from another thread does not return; once released, it does.
TEST(MapBuilderThreads, gettersAndChangesTakeTheCriticalSection)
{
	CLockableBuilder builder;
	const std::vector<std::pair<const char*, std::function<void()>>> calls = {
		{"getCurrentPoseEstimation", [&] { builder.getCurrentPoseEstimation(); }},
		{"getCurrentlyBuiltMap",
		 [&]
		 {
			 mrpt::maps::CSimpleMap m;
			 builder.getCurrentlyBuiltMap(m);
		 }},
		{"getCurrentlyBuiltMapSize", [&] { builder.getCurrentlyBuiltMapSize(); }},
		{"getCurrentlyBuiltMetricMap", [&] { builder.getCurrentlyBuiltMetricMap(); }},
		{"trajectory", [&] { builder.trajectory(); }},
		{"buildOccupancyGrid", [&] { builder.buildOccupancyGrid(); }},
		{"statsCopy", [&] { builder.statsCopy(); }},
		{"loopCloserStats", [&] { builder.loopCloserStats(); }},
		{"lastScanTimestamp", [&] { builder.lastScanTimestamp(); }},
		{"takeWarnings", [&] { builder.takeWarnings(); }},
		{"finish", [&] { builder.finish(); }},
		{"processObservation",
		 [&]
		 {
			 auto odo = mrpt::obs::CObservationOdometry::Create();
			 builder.processObservation(odo);
		 }},
	};
	for (const auto& [name, call] : calls)
	{
		builder.enterCriticalSection();
		std::atomic<bool> returned{false};
		std::thread t(
			[&]
			{
				call();
				returned = true;
			});
		std::this_thread::sleep_for(std::chrono::milliseconds(50));
		EXPECT_FALSE(returned) << name << " returned while the critical section was held";
		builder.leaveCriticalSection();
		t.join();
		EXPECT_TRUE(returned) << name;
	}
}

// [LoopCloser] worker_budget_ms: results land where a worker doing that much modelled work per
// keyframe would finish them, and searches are skipped past max_backlog_keyframes. A budget far
// below what the searches cost delays results and sheds searches; the schedule still depends on
// the data alone, so a slowed worker gives the same map.
TEST(LoopClosingWorker, aModelledWorkerDelaysCostlyResultsAndShedsSearchesWhateverItsSpeed)
{
	TLRGCParams p;
	p.loop.worker_budget_ms = 0.2;
	p.loop.max_backlog_keyframes = 6;
	const TWorkerRun normal = mapRing(p, std::chrono::milliseconds(0));
	const TWorkerRun slow = mapRing(p, std::chrono::milliseconds(15));
	p.loop.background = false;
	const TWorkerRun inlineRun = mapRing(p, std::chrono::milliseconds(0));

	EXPECT_GT(normal.stats.loopResultDelayMax, p.loop.result_delay_keyframes);
	EXPECT_GT(normal.loop.searchesShed, 0U);
	EXPECT_EQ(normal.loop.searchesShed, slow.loop.searchesShed);
	// Where: one keyframe per search shed, in order, the same whatever the worker's speed.
	EXPECT_EQ(normal.loop.shedKeyframes.size(), normal.loop.searchesShed);
	EXPECT_TRUE(
		std::is_sorted(normal.loop.shedKeyframes.begin(), normal.loop.shedKeyframes.end()));
	EXPECT_EQ(normal.loop.shedKeyframes, slow.loop.shedKeyframes);
	expectSameWorkerTrajectory(normal.trajectory, slow.trajectory, "slowed worker");
	expectSameWorkerTrajectory(normal.trajectory, inlineRun.trajectory, "no worker thread");
	EXPECT_EQ(normal.stats.loopClosureLinks, slow.stats.loopClosureLinks);
}

// Issue 28: while the modelled worker is behind, searches are thinned out, never stopped: a
// search runs every patch_min_keyframes keyframes, so every keyframe whose search was shed lies
// in the patch of the next search that ran (a patch is at least patch_min_keyframes long), and
// no place goes unsearched. Before, every search was shed until the worker caught up: runs of
// up to 138 keyframes on MIT Killian.
TEST(LoopClosingWorker, searchesShedWhileBehindLieInTheNextSearchsPatch)
{
	TLRGCParams p;
	p.loop.worker_budget_ms = 0.2;
	p.loop.max_backlog_keyframes = 6;
	const TWorkerRun run = mapRing(p, std::chrono::milliseconds(0));
	const auto& shed = run.loop.shedKeyframes;
	ASSERT_GT(shed.size(), 0U) << "the worker must fall behind for this test";
	size_t longest = 1, current = 1;
	for (size_t i = 1; i < shed.size(); ++i)
	{
		current = shed[i] == shed[i - 1] + 1 ? current + 1
				  : shed[i] == shed[i - 1]   ? current
											 : 1;
		longest = std::max(longest, current);
	}
	::testing::Test::RecordProperty("searches_shed", std::to_string(shed.size()));
	::testing::Test::RecordProperty("longest_run_shed", std::to_string(longest));
	EXPECT_LT(longest, p.loop.patch_min_keyframes)
		<< "consecutive keyframes shed: a place no search's patch covered";
	// Each deferred search is counted as merged into the next search that ran, none dropped.
	EXPECT_EQ(run.loop.searchesMerged, run.loop.searchesShed);
	EXPECT_TRUE(run.loop.droppedKeyframes.empty());
}

// Issue 28: the worker's budget follows the data ([LoopCloser] worker_budget_span). The same
// ring driven slowly (2 s between scans) with a per-keyframe budget far below what its
// searches cost: with the budget per keyframe alone (main) the worker falls behind, searches
// are deferred, the revisit's among them, and the loop stays open (1.0 m off at the end);
// with the budget per keyframe spacing travelled fewer are deferred and the loop closes. No
// deferred search is lost: each is merged into a later search whose patch holds its keyframe
// (the run's end searches too).
TEST(LoopClosingWorker, aBudgetPerSpacingTravelledClosesTheLoopASlowRobotRevisits)
{
	constexpr double kSlowScanPeriod = 2.0;  // [s] between scans; keyframes 4-6 s apart
	// [ms] Far below what a search costs. 0.5 until the calibrated gate became the default:
	// its windows' searches cost less, and at 0.2-0.5 the per-keyframe run closed the loop
	// too (53-61 deferred, 0.01 m); at 0.08-0.15 it stays open (1.0 m, 63-82 deferred) and
	// the per-spacing run closes it (0.004-0.021 m).
	constexpr double kPerKeyframeBudgetMs = 0.1;
	// [keyframe spacings] The ring's keyframes span 1-1.3 spacings of travel: each grants
	// 3.3-4x the per-keyframe budget (the cap), as a sparse log's keyframes spanning 3-5
	// spacings do with the default 1.5.
	constexpr double kBudgetSpan = 0.3;
	TLRGCParams p;
	p.loop.worker_budget_ms = kPerKeyframeBudgetMs;
	p.loop.max_backlog_keyframes = 6;
	// The online search is on trial: the end-of-run revisit sweep, which now reaches back
	// 15 keyframes and 20 m of path, links the ring's revisit whatever the worker did
	// (0.05 m at the end with the per-keyframe budget).
	p.revisits.enabled = false;
	p.loop.worker_budget_span = 0;  // main: the same budget per keyframe whatever the travel
	const TWorkerRun perKeyframe =
		mapRing(p, std::chrono::milliseconds(0), {}, kSlowScanPeriod);
	p.loop.worker_budget_span = kBudgetSpan;
	const TWorkerRun perSecond = mapRing(p, std::chrono::milliseconds(0), {}, kSlowScanPeriod);
	const TWorkerRun slow = mapRing(p, std::chrono::milliseconds(15), {}, kSlowScanPeriod);
	::testing::Test::RecordProperty("deferred_per_keyframe",
									std::to_string(perKeyframe.loop.searchesShed));
	::testing::Test::RecordProperty("error_per_keyframe_m",
									std::to_string(perKeyframe.error.finalXY));
	::testing::Test::RecordProperty("error_per_second_m",
									std::to_string(perSecond.error.finalXY));

	EXPECT_GT(perKeyframe.loop.searchesShed, 0U) << "the per-keyframe budget must fall behind";
	EXPECT_EQ(perKeyframe.stats.loopClosures, 0U);
	EXPECT_GT(perKeyframe.error.finalXY, 0.3);

	EXPECT_LT(perSecond.loop.searchesShed, perKeyframe.loop.searchesShed);
	EXPECT_GT(perSecond.stats.loopClosures, 0U);
	EXPECT_LT(perSecond.error.finalXY, 0.3);
	for (const TWorkerRun* run : {&perKeyframe, &perSecond})
	{  // deferred, never lost: each merged into a later search (the run's end searches too)
		EXPECT_EQ(run->loop.searchesMerged, run->loop.searchesShed);
		EXPECT_TRUE(run->loop.droppedKeyframes.empty());
	}
	expectSameWorkerTrajectory(perSecond.trajectory, slow.trajectory, "slowed worker");
}

// Issue 28: dense scans keep the per-keyframe schedule. At 5 scans per second the ring's
// keyframes are taken just past one spacing of travel (below the default span of 1.5), so the
// budget per spacing grants worker_budget_ms per keyframe, exactly main's (span 0): the same
// searches deferred and the same trajectory. A budget that grew with anything else (the log's
// seconds, a stop) would move the schedule here.
TEST(LoopClosingWorker, denseKeyframesKeepThePerKeyframeBudget)
{
	TLRGCParams p;
	p.loop.worker_budget_ms = 0.2;  // far behind: the schedule decides which searches run
	p.loop.max_backlog_keyframes = 6;
	ASSERT_GT(p.loop.worker_budget_span, 1.0);
	const TWorkerRun perSpan = mapRing(p, std::chrono::milliseconds(0));
	p.loop.worker_budget_span = 0;
	const TWorkerRun perKeyframe = mapRing(p, std::chrono::milliseconds(0));
	ASSERT_GT(perKeyframe.loop.searchesShed, 0U) << "the worker must fall behind for this test";
	EXPECT_EQ(perSpan.loop.shedKeyframes, perKeyframe.loop.shedKeyframes);
	expectSameWorkerTrajectory(perSpan.trajectory, perKeyframe.trajectory,
							   "budget per spacing");
	// The check can fail: a span below the keyframes' own (0.5: 2-2.6x the budget) moves it.
	p.loop.worker_budget_span = 0.5;
	const TWorkerRun moreBudget = mapRing(p, std::chrono::milliseconds(0));
	EXPECT_NE(moreBudget.loop.shedKeyframes, perKeyframe.loop.shedKeyframes);
}

TEST(LoopWork, theModelIsLinearInTheCounts)
{
	lrgc::TLoopWork a, b;
	a.correlations = 2, a.correlationPoseCells = 1e6, a.solveElements = 1e4;
	b.correlations = 1, b.solveIterationElements = 5e4, b.newScans = 3;
	lrgc::TLoopWork sum = a;
	sum += b;
	EXPECT_NEAR(sum.referenceMs(), a.referenceMs() + b.referenceMs(), 1e-9);
	EXPECT_NEAR((sum - b).referenceMs(), a.referenceMs(), 1e-9);
	EXPECT_EQ(lrgc::TLoopWork{}.referenceMs(), 0.0);
	lrgc::TLoopWork more = a;
	more.correlationPoseCells *= 2;
	EXPECT_GT(more.referenceMs(), a.referenceMs());
}
