/* CViewContradiction: a place that changed between the map's passes is no kidnap; a wrong
 * place still is. Fails on main (56adc76), whose kidnap rule asked the joined cloud only. */
#include <gtest/gtest.h>
#include <lrgc/common/se2.h>
#include <lrgc/localization/Localizer.h>
#include <lrgc/localization/ViewContradiction.h>
#include <lrgc/scan_matching/ScanMatcherParams.h>

#include <random>

#include "synthetic_world.h"

using namespace lrgc;
using namespace lrgc::test;
using mrpt::math::TPose2D;

namespace
{
/** A room whose right wall (x = 3) has two doorways, y in [0.5, 3.5] and [-3.5, -0.5], each
 * to an alcove 4 m deep; `open1`, `open2`: which doors stand open. */
CSyntheticWorld roomWithTwoDoors(bool open1, bool open2)
{
	CSyntheticWorld w;
	w.addPolygon({{-3, -6},
				  {3, -6},
				  {3, -3.5},
				  {7, -3.5},
				  {7, -0.5},
				  {3, -0.5},
				  {3, 0.5},
				  {7, 0.5},
				  {7, 3.5},
				  {3, 3.5},
				  {3, 6},
				  {-3, 6}});
	if (!open1) w.addSegment({3, 0.5}, {3, 3.5});
	if (!open2) w.addSegment({3, -3.5}, {3, -0.5});
	return w;
}

/** Pass A (nodes 0-2: door 1 open, door 2 shut) and pass B (nodes 6-8: the other way round)
 * at the room's middle, nodes 3-5 (another pass) 50 m away. */
void mapTwoPasses(CPoseGraph& map, TKeyframes& keyframes, std::mt19937& rng)
{
	const CSyntheticWorld passA = roomWithTwoDoors(true, false),
						  passB = roomWithTwoDoors(false, true);
	for (int node = 0; node < 9; ++node)
	{
		const bool far = node >= 3 && node < 6;
		const TPose2D pose(far ? 50.0 : -0.3 + 0.3 * (node % 3), far ? 50.0 : 0.1 * (node % 3),
						   0.05 * (node % 3));
		map.addNode(pose);
		TKeyframe kf;
		kf.scan =
			simulateScan(node < 3 ? passA : passB, far ? TPose2D(0, 0, 0) : pose, {}, rng);
		keyframes.push_back(std::move(kf));
	}
}
/** A scan in a corridor 2 m wide: a robot carried off, somewhere else than the room. */
TScan2D corridorScan(std::mt19937& rng)
{
	CSyntheticWorld corridor;
	corridor.addSegment({-5, 1}, {25, 1});
	corridor.addSegment({-5, -1}, {25, -1});
	return simulateScan(corridor, TPose2D(0, 0, 0), {}, rng);
}
}  // namespace

TEST(ViewContradiction, passesAreRunsOfKeyframeIndicesOfThreeToTen)
{
	const auto passes = CViewContradiction::passesOf({12, 0, 1, 2, 4, 30, 31, 10, 11});
	ASSERT_EQ(passes.size(), 2U);  // 0-4 (gaps of at most 2), 10-12; 30-31 too few
	EXPECT_EQ(passes[0], (std::vector<size_t>{0, 1, 2, 4}));
	EXPECT_EQ(passes[1], (std::vector<size_t>{10, 11, 12}));
	// A long pass in parts of at most kMaxPassKeyframes; a remainder too short joins the last.
	std::vector<size_t> run25(25), run12(12);
	for (size_t i = 0; i < 25; ++i) run25[i] = 100 + i;
	for (size_t i = 0; i < 12; ++i) run12[i] = 200 + i;
	const auto parts25 = CViewContradiction::passesOf(run25);
	ASSERT_EQ(parts25.size(), 3U);
	EXPECT_EQ(parts25[0].size(), 10U);
	EXPECT_EQ(parts25[2].front(), 120U);
	EXPECT_EQ(parts25[2].size(), 5U);
	const auto parts12 = CViewContradiction::passesOf(run12);
	ASSERT_EQ(parts12.size(), 1U);
	EXPECT_EQ(parts12[0].size(), 12U);
}

// Both doors shut now: against the two passes joined, the scan's door 1 lies where pass A saw
// through and its door 2 where pass B did (main called that a kidnap); against each pass on
// its own it agrees. Believed in that room while in a corridor, it contradicts both passes.
TEST(ViewContradiction, aPlaceThatChangedBetweenPassesIsNoContradictionAWrongPlaceIs)
{
	std::mt19937 rng(5);
	CPoseGraph map;
	TKeyframes keyframes;
	mapTwoPasses(map, keyframes, rng);
	const TScanMatcherParams p;
	const double margin = 0.2, fraction = 0.3;
	const TPose2D here(0.05, 0.05, 0.02);
	const TScan2D bothShut = simulateScan(roomWithTwoDoors(false, false), here, {}, rng);
	const std::vector<size_t> near{0, 1, 2, 6, 7, 8};

	std::vector<TScan2D> scans;
	std::vector<TPose2D> poses;
	for (const size_t i : near)
		scans.push_back(keyframes[i].scan), poses.push_back(map.pose(i));
	const auto joined = CReferenceCloud::fromScans(scans, poses, p);
	EXPECT_GE(joined.freeSpaceViolation(bothShut, here, margin), fraction);

	CViewContradiction views(map, keyframes, p);
	EXPECT_FALSE(views.contradictsEveryPass(bothShut, here, near, margin, fraction));

	const TScan2D elsewhere = corridorScan(rng);
	EXPECT_GE(joined.freeSpaceViolation(elsewhere, here, margin), fraction);
	EXPECT_TRUE(views.contradictsEveryPass(elsewhere, here, near, margin, fraction));
}

// Tracking's free-space verdict (CLocalizer::refusedByFreeSpace; does not build on main, whose
// tracking took the joined reference's check as final): the scan with both doors shut, at the
// right pose, is refused by the joined cloud yet stands, fitting tightly and agreeing with each
// pass; the same violation with a loose fit, too few points matched, or in a corridor elsewhere
// is refused. ACES localised on its own map: 298 -> 129 poor matches, no false kidnap.
TEST(ViewContradiction, trackingKeepsATightMatchInAPlaceThatChangedBetweenPasses)
{
	std::mt19937 rng(5);
	CPoseGraph map;
	TKeyframes keyframes;
	mapTwoPasses(map, keyframes, rng);
	const TScanMatcherParams p;
	const double margin = 0.2, limit = 0.3;
	const TPose2D here(0.05, 0.05, 0.02);
	const TScan2D bothShut = simulateScan(roomWithTwoDoors(false, false), here, {}, rng);
	const std::vector<size_t> near{0, 1, 2, 6, 7, 8};
	CViewContradiction views(map, keyframes, p);

	TScanMatch tight;
	tight.inlierFraction = 0.9;
	tight.rmsResidual = 0.01;
	tight.freeSpaceViolation = 0.4;  // the joined cloud's word (measured in the test above)
	EXPECT_FALSE(
		CLocalizer::refusedByFreeSpace(tight, limit, views, bothShut, here, near, margin));

	TScanMatch loose = tight;
	loose.rmsResidual = 2 * CLocalizer::kChangedPlaceRms_m;
	EXPECT_TRUE(
		CLocalizer::refusedByFreeSpace(loose, limit, views, bothShut, here, near, margin));
	TScanMatch partial = tight;
	partial.inlierFraction = CLocalizer::kKeepInlierFraction - 0.1;
	EXPECT_TRUE(
		CLocalizer::refusedByFreeSpace(partial, limit, views, bothShut, here, near, margin));

	const TScan2D elsewhere = corridorScan(rng);
	EXPECT_TRUE(
		CLocalizer::refusedByFreeSpace(tight, limit, views, elsewhere, here, near, margin));
	// Under the limit the joined check passed: nothing more is asked.
	TScanMatch agreeing = loose;
	agreeing.freeSpaceViolation = 0.1;
	EXPECT_FALSE(
		CLocalizer::refusedByFreeSpace(agreeing, limit, views, elsewhere, here, near, margin));
}
