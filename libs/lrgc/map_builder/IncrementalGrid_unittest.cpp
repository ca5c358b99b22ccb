/* CIncrementalGrid against a grid built from scratch, cell for cell, over random sequences of
 * appended keyframes, moved window keyframes and moved old keyframes (loop closures), with
 * scans taken again and again in one small room so that cells reach MRPT's log-odds clamp
 * (where removing a scan could not be exact). The real-log check is
 * tests/incremental_grid_test.cpp. */
#include <gtest/gtest.h>
#include <lrgc/map_builder/IncrementalGrid.h>

#include <random>

#include "synthetic_world.h"

namespace
{
using lrgc::CIncrementalGrid;
using lrgc::TGridKeyframe;
using lrgc::TGridKeyframes;
using Update = CIncrementalGrid::Update;

/** A 180 deg, 181-beam scan of `world` from `pose` (20 m; no return: invalid ray). */
mrpt::obs::CObservation2DRangeScan::Ptr scanOf(const lrgc::test::CSyntheticWorld& world,
											   const mrpt::math::TPose2D& pose)
{
	auto scan = mrpt::obs::CObservation2DRangeScan::Create();
	scan->aperture = static_cast<float>(M_PI);
	scan->maxRange = 20.0f;
	scan->resizeScan(181);
	for (size_t b = 0; b < 181; ++b)
	{
		const auto r = world.castRay({pose.x, pose.y}, pose.phi + scan->getScanAngle(b), 20.0);
		scan->setScanRange(b, r ? static_cast<float>(*r) : 20.0f);
		scan->setScanRangeValidity(b, r.has_value());
	}
	return scan;
}

/** The reference, written out here rather than taken from the class under test: MRPT's grid,
 * each keyframe inserted in order at its current pose. */
mrpt::maps::COccupancyGridMap2D freshGrid(const TGridKeyframes& keyframes,
										  const lrgc::TGridSettings& s)
{
	mrpt::maps::COccupancyGridMap2D grid(-10, 10, -10, 10, static_cast<float>(s.resolution));
	grid.insertionOptions.maxDistanceInsertion = static_cast<float>(s.maxRayLength);
	for (const auto& k : keyframes)
		grid.insertObservation(*k.laser, mrpt::poses::CPose3D(k.robotInMap.x, k.robotInMap.y, 0,
															  k.robotInMap.phi, 0, 0));
	return grid;
}

/** Number of cells that differ (every cell if the extents differ). */
size_t differingCells(const mrpt::maps::COccupancyGridMap2D& a,
					  const mrpt::maps::COccupancyGridMap2D& b)
{
	if (a.getSizeX() != b.getSizeX() || a.getSizeY() != b.getSizeY() ||
		a.getXMin() != b.getXMin() || a.getYMin() != b.getYMin() ||
		a.getResolution() != b.getResolution())
		return std::max(a.getRawMap().size(), b.getRawMap().size());
	size_t n = 0;
	for (size_t i = 0; i < a.getRawMap().size(); ++i) n += a.getRawMap()[i] != b.getRawMap()[i];
	return n;
}
}  // namespace

TEST(IncrementalGrid, EqualsAFreshBuildAfterRandomAppendsAndMoves)
{
	const auto world = lrgc::test::makeRoomWorld(5);
	std::mt19937 rng(42);
	std::uniform_real_distribution<double> u(0, 1);
	lrgc::TGridSettings settings;
	settings.resolution = 0.1;
	settings.settleKeyframes = 6;
	CIncrementalGrid grid(settings);
	TGridKeyframes kfs;
	auto randomPose = [&]
	{ return mrpt::math::TPose2D(2 + 6 * u(rng), 1.5 + 4 * u(rng), M_PI * (2 * u(rng) - 1)); };
	auto nudge = [&](TGridKeyframe& k)
	{
		// Moves of up to 5 cm (half a cell), and of 1e-12 m: any change counts.
		const double scale = u(rng) < 0.3 ? 1e-12 : 0.05 * u(rng);
		k.robotInMap.x += scale, k.robotInMap.phi += 0.5 * scale;
	};
	size_t clampedCells = 0;
	for (int step = 0; step < 300; ++step)
	{
		const double what = u(rng);
		// New keyframes: a few, or a burst of 10 (a caller that asks rarely).
		if (what < 0.45 || kfs.empty())
			for (int k = u(rng) < 0.1 ? 10 : 1 + int(3 * u(rng)); k > 0; --k)
			{
				const auto pose = randomPose();
				kfs.push_back({pose, scanOf(world, pose)});
			}
		else if (what < 0.7)  // the local window moves its newest keyframes
			for (size_t i = kfs.size() > 5 ? kfs.size() - 5 : 0; i < kfs.size(); ++i)
				nudge(kfs[i]);
		else if (what < 0.85)  // a loop closure moves old keyframes too
			for (size_t i = size_t(u(rng) * kfs.size()); i < kfs.size(); ++i) nudge(kfs[i]);
		else if (what < 0.9)  // a keyframe given a new scan: recognised by address
			kfs[size_t(u(rng) * kfs.size())].laser = scanOf(world, randomPose());
		else if (what < 0.95)  // fewer keyframes (a new map): the newest dropped
			kfs.resize(size_t(u(rng) * kfs.size()));
		// else: nothing changed
		grid.update(kfs);
		const auto fresh = freshGrid(kfs, settings);
		ASSERT_EQ(differingCells(*grid.grid(), fresh), 0u)
			<< "step " << step << ", " << kfs.size() << " keyframes";
		if (step == 299)
			for (const auto c : fresh.getRawMap())
				clampedCells += c == mrpt::maps::COccupancyGridMap2D::OCCGRID_CELLTYPE_MIN ||
								c == mrpt::maps::COccupancyGridMap2D::OCCGRID_CELLTYPE_MAX;
	}
	// Every path was taken, and the scans saturated cells (the clamp was exercised).
	EXPECT_GT(grid.count(Update::Unchanged), 0u);
	EXPECT_GT(grid.count(Update::Appended), 10u);
	EXPECT_GT(grid.count(Update::TailReinserted), 10u);
	EXPECT_GT(grid.count(Update::Rebuilt), 5u);
	EXPECT_GT(clampedCells, 100u);
	EXPECT_EQ(differingCells(*CIncrementalGrid::buildFromScratch(kfs, settings),
							 freshGrid(kfs, settings)),
			  0u);
}

TEST(IncrementalGrid, OnlyNewKeyframesAreInsertedWhenNothingMoved)
{
	const auto world = lrgc::test::makeRoomWorld(6);
	lrgc::TGridSettings settings;
	settings.settleKeyframes = 3;
	CIncrementalGrid grid(settings);
	TGridKeyframes kfs;
	const auto objectBefore = grid.grid().get();
	for (int i = 0; i < 10; ++i)
	{
		const mrpt::math::TPose2D pose(2 + 0.5 * i, 3, 0.1 * i);
		kfs.push_back({pose, scanOf(world, pose)});
		EXPECT_EQ(grid.update(kfs), Update::Appended);
		EXPECT_EQ(grid.update(kfs), Update::Unchanged);
	}
	EXPECT_EQ(grid.grid().get(), objectBefore) << "the grid object must stay the same";
	kfs[8].robotInMap.y += 0.01;  // in the tail
	EXPECT_EQ(grid.update(kfs), Update::TailReinserted);
	kfs[1].robotInMap.y += 0.01;  // in the base
	EXPECT_EQ(grid.update(kfs), Update::Rebuilt);
	kfs.pop_back();  // fewer keyframes (a new map) also works
	EXPECT_NE(grid.update(kfs), Update::Unchanged);
	EXPECT_EQ(differingCells(*grid.grid(), freshGrid(kfs, settings)), 0u);
	EXPECT_EQ(grid.grid().get(), objectBefore);
}

TEST(IncrementalGrid, ANewerSessionShowsTheCellsItSawAsItSawThem)
{
	// Session 0 sees a box at (6, 3.5); by session 1 it is gone and another stands at
	// (4, 5.5). Session 1 only looks east from x = 2, so the west wall is session 0's alone.
	auto before = lrgc::test::makeRoomWorld(7, 0), after = before;
	before.addBox({6, 3.5}, 0.3, 0.3);
	after.addBox({4, 5.5}, 0.3, 0.3);
	lrgc::TGridSettings settings;
	CIncrementalGrid grid(settings);
	TGridKeyframes kfs;
	for (int i = 0; i < 12; ++i)
	{
		const mrpt::math::TPose2D pose(2 + 0.3 * (i % 4), 2 + 0.2 * i, M_PI / 3 * i);
		kfs.push_back({pose, scanOf(before, pose), 0});
	}
	grid.update(kfs);
	auto occupied = [&](double x, double y) { return grid.grid()->getPos(x, y) < 0.5f; };
	EXPECT_TRUE(occupied(5.71, 3.5));
	EXPECT_FALSE(occupied(3.71, 5.5));
	EXPECT_TRUE(occupied(0.01, 3.5));
	const auto object = grid.grid().get();
	for (int i = 0; i < 6; ++i)
	{
		const mrpt::math::TPose2D pose(2, 1.5 + 0.5 * i, 0.2 * (i - 3));
		kfs.push_back({pose, scanOf(after, pose), 1});
		EXPECT_EQ(grid.update(kfs), Update::Rebuilt);
	}
	EXPECT_FALSE(occupied(5.71, 3.5)) << "the box session 1 saw gone is still in the map";
	EXPECT_TRUE(occupied(3.71, 5.5)) << "the box session 1 saw is not in the map";
	EXPECT_TRUE(occupied(0.01, 3.5)) << "what only session 0 saw must stay";
	EXPECT_EQ(grid.update(kfs), Update::Unchanged);
	EXPECT_EQ(grid.grid().get(), object) << "the grid object must stay the same";
	EXPECT_EQ(differingCells(*grid.grid(), *CIncrementalGrid::buildFromScratch(kfs, settings)),
			  0u);
	// Back to one session (the newer keyframes dropped): the plain fold again.
	kfs.resize(12);
	grid.update(kfs);
	EXPECT_EQ(differingCells(*grid.grid(), freshGrid(kfs, settings)), 0u);
	EXPECT_TRUE(occupied(5.71, 3.5));
}
