#include "changed_world.h"

#include <lrgc/common/se2.h>

#include <algorithm>
#include <cmath>
#include <set>

namespace lrgc::test
{
namespace
{
/** The hall without its movable objects: walls, partition with its doorway, store room,
 * pillars. */
CSyntheticWorld fixedHall()
{
	CSyntheticWorld w;
	w.addPolygon({{0, 0}, {30, 0}, {30, 20}, {0, 20}});
	w.addSegment({24, 0}, {24, 9});  // the partition, a doorway y in [9, 10.2]
	w.addSegment({24, 10.2}, {24, 20});
	w.addBox({27, 9.6}, 0.25, 0.25);  // a crate in the store room, seen through the door
	for (const double x : {7.5, 15.0, 19.0})
		for (const double y : {6.5, 13.5}) w.addCircle({x, y}, 0.25);
	return w;
}

/** A cabinet (1.2 x 0.5 m) at `centre`, turned by `angle` [rad]. */
void addCabinet(CSyntheticWorld& w, const Eigen::Vector2d& centre, double angle = 0)
{
	w.addBox(centre, 0.6, 0.25, angle);
}
}  // namespace

TChangedHall makeChangedHall()
{
	TChangedHall h;
	addCabinet(h.removed, {6, 4});
	addCabinet(h.removed, {17, 15.5});
	addCabinet(h.removed, {9.5, 7.5});
	addCabinet(h.removed, {19, 12.5});
	h.removed.addBox({8, 15.5}, 1.5, 0.2);  // the shelf

	addCabinet(h.added, {15, 4});
	addCabinet(h.added, {6, 13});
	addCabinet(h.added, {17, 7}, M_PI / 2);
	addCabinet(h.added, {8, 11.5});
	h.added.addBox({17, 16.8}, 1.5, 0.2);     // the shelf
	h.added.addSegment({24, 9}, {24, 10.2});  // the door, closed

	const CSyntheticWorld hall = fixedHall();
	h.before = hall;
	h.before.addWorld(h.removed, {0, 0});
	h.after = hall;
	h.after.addWorld(h.added, {0, 0});
	return h;
}

TOutlineCells outlineCells(const mrpt::maps::COccupancyGridMap2D& grid,
						   const mrpt::math::TPose2D& mapInWorld,
						   const CSyntheticWorld& outlines, const CSyntheticWorld& other,
						   double keepOff, int slack)
{
	const mrpt::math::TPose2D worldInMap = lrgc::inverse(mapInWorld);
	const double step = grid.getResolution() / 4;
	std::set<std::pair<int, int>> cells;
	for (const TSegment& s : outlines.segments())
	{
		const int n = std::max(1, int(std::ceil((s.b - s.a).norm() / step)));
		for (int i = 0; i <= n; ++i)
		{
			const Eigen::Vector2d p = s.a + (s.b - s.a) * (double(i) / n);
			if (other.distanceToNearest(p) < keepOff) continue;
			const Eigen::Vector2d q = lrgc::transformPoint(worldInMap, p);
			cells.insert({grid.x2idx(q.x()), grid.y2idx(q.y())});
		}
	}
	TOutlineCells out;
	for (const auto& [cx, cy] : cells)
	{
		++out.cells;
		if (cx < 0 || cy < 0 || cx >= int(grid.getSizeX()) || cy >= int(grid.getSizeY()))
			continue;
		if (grid.getRawMap()[size_t(cx) + size_t(cy) * grid.getSizeX()] == 0) continue;
		++out.known;
		// getCell is the probability of the cell being free (MRPT's convention).
		bool occupied = false;
		for (int dy = -slack; dy <= slack; ++dy)
			for (int dx = -slack; dx <= slack; ++dx)
				occupied = occupied || grid.getCell(cx + dx, cy + dy) < 0.5f;
		out.occupied += occupied;
	}
	return out;
}

}  // namespace lrgc::test
