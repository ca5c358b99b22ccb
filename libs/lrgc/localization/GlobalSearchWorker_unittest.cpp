/* CGlobalSearchWorker: a search's result lands at the log time the modelled worker finishes
 * it (t_submit + W / budget), whether it ran on a thread of its own or on the caller's, and
 * not before; the located pose is the one the map was seen from. A synthetic room (seeded)
 * is the map: keyframes at four poses, the patch a scan from a fifth. */
#include <gtest/gtest.h>
#include <lrgc/common/se2.h>
#include <lrgc/localization/GlobalSearchWorker.h>

#include "synthetic_world.h"

using namespace lrgc;
using mrpt::math::TPose2D;

namespace
{
struct TRoomMap
{
	CPoseGraph graph;
	TKeyframes keyframes;
	std::vector<Eigen::Vector2d> patch;  //!< a scan from `truth`, in its frame
	TPose2D truth{4.2, 2.7, 0.6};
};

TRoomMap roomMap()
{
	const auto world = test::makeRoomWorld(42);
	std::mt19937 rng(7);
	const test::TLaserSimParams laser;
	TRoomMap m;
	const auto b = world.bounds();
	for (const auto& p : {TPose2D(b.min.x() + 1.5, b.min.y() + 1.5, 0.3),
						  TPose2D(b.max.x() - 1.5, b.min.y() + 1.5, 2.0),
						  TPose2D(b.max.x() - 1.5, b.max.y() - 1.5, -2.5),
						  TPose2D(b.min.x() + 1.5, b.max.y() - 1.5, -1.0)})
	{
		m.graph.addNode(p);
		TKeyframe kf;
		kf.scan = test::simulateScan(world, p, laser, rng);
		m.keyframes.push_back(std::move(kf));
	}
	m.truth =
		TPose2D(0.5 * (b.min.x() + b.max.x()) + 0.4, 0.5 * (b.min.y() + b.max.y()) - 0.3, 0.6);
	m.patch = test::simulateScan(world, m.truth, laser, rng).points;
	return m;
}

/** The first of the log times 0, 0.01, 0.02, ... [s] at which the result is taken. */
std::pair<double, TGlobalLocation> takenAt(CGlobalSearchWorker& worker)
{
	for (int i = 0; i < 100000; ++i)
		if (auto r = worker.takeIfDue(0.01 * i)) return {0.01 * i, *r};
	return {-1, {}};
}
}  // namespace

TEST(GlobalSearchWorker, resultLandsWhereTheModelledWorkerFinishesIt)
{
	const TRoomMap m = roomMap();
	const CGlobalLocalizer localizer(m.graph, m.keyframes, TPatchCorrelatorParams{});
	const double budget = 200;  // [ms of modelled work per s of log]
	std::vector<std::pair<double, TGlobalLocation>> runs;
	for (const bool background : {false, true})
	{
		CGlobalSearchWorker worker(localizer, budget, background);
		EXPECT_FALSE(worker.busy());
		EXPECT_FALSE(worker.takeIfDue(1e9)) << "nothing submitted";
		worker.submit({m.patch, localizer.wholeMap(), 0.0});
		EXPECT_TRUE(worker.busy());
		runs.push_back(takenAt(worker));
		EXPECT_FALSE(worker.busy());
		EXPECT_EQ(worker.searchesOnCallerThread(), background ? 0U : 1U);
	}
	for (const auto& [at, loc] : runs)
	{
		ASSERT_GE(at, 0) << "never taken";
		ASSERT_TRUE(loc.accepted()) << loc.verdict.message();
		const double due = loc.modelledMs / budget;
		EXPECT_GE(at, due - 1e-9) << "taken before the modelled worker finished";
		EXPECT_LT(at, due + 0.01 + 1e-9) << "taken later than the first time at or after due";
		const TPose2D err = between(m.truth, loc.correlation->patchInMap);
		EXPECT_LT(translationNorm(err), 0.1);
		EXPECT_LT(std::abs(err.phi), 0.05);
	}
	// The same result and the same landing time, thread or not.
	EXPECT_EQ(runs[0].first, runs[1].first);
	EXPECT_EQ(runs[0].second.modelledMs, runs[1].second.modelledMs);
	EXPECT_GT(runs[0].second.modelledMs, 0);
}

TEST(GlobalSearchWorker, aWindowAroundTheTruthCostsLessThanTheWholeMap)
{
	const TRoomMap m = roomMap();
	const CGlobalLocalizer localizer(m.graph, m.keyframes, TPatchCorrelatorParams{});
	TSearchArea near;
	near.centre = TPose2D(m.truth.x + 0.3, m.truth.y - 0.2, m.truth.phi + 0.1);
	near.halfXY = 1.0, near.halfTheta = 0.35;
	const auto local = localizer.locate(m.patch, localizer.clipped(near));
	const auto whole = localizer.locate(m.patch);
	ASSERT_TRUE(local.accepted()) << local.verdict.message();
	EXPECT_LT(translationNorm(between(m.truth, local.correlation->patchInMap)), 0.1);
	EXPECT_LT(local.modelledMs, 0.5 * whole.modelledMs);
	// A window wider than the map searches the whole map's positions, no more.
	near.halfXY = 1e3;
	EXPECT_EQ(localizer.clipped(near).halfXY, localizer.wholeMap().halfXY);
}
