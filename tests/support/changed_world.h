/* A hall whose furniture moves between two mapping sessions (issue 29: a map that shows a
 * changed world), and the measure of how an occupancy grid shows it.
 *
 * The hall, corners (0,0)-(30,20), is closed on the east by a partition at x = 24 with a
 * 1.2 m doorway (y in [9, 10.2]) onto a store room. Six 0.25 m pillars stand 7.5 m apart (the
 * fixed features). The movable objects: four cabinets (1.2 x 0.5 m) and a shelf (3 x 0.4 m)
 * free-standing in the hall, each elsewhere in the second session, and the door, open in the
 * first session and closed in the second. Every object keeps 0.5 m clear of the routes
 * (x = 2, x = 12, x = 22, y = 2, y = 10, y = 18), in both sessions.
 *
 * Frames: world coordinates [m]; a grid's map frame is given by (world <- map).
 */
#pragma once

#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/math/TPose2D.h>

#include <Eigen/Core>
#include <vector>

#include "synthetic_world.h"

namespace lrgc::test
{
/** The hall in each session and its movable objects, each as a world of its own. */
struct TChangedHall
{
	CSyntheticWorld before, after;  //!< the whole hall in session 1 and in session 2
	/** The objects that are only in `before` (removed) and only in `after` (new). */
	CSyntheticWorld removed, added;
};
TChangedHall makeChangedHall();

/** How a grid shows a set of object outlines: of the outline cells the grid knows (a cell
 * whose log-odds is not 0, i.e. some ray ended in it or crossed it), the occupied share. */
struct TOutlineCells
{
	size_t cells = 0;     //!< distinct outline cells
	size_t known = 0;     //!< of them, known to the grid
	size_t occupied = 0;  //!< of the known, occupancy > 0.5
	double occupiedShare() const { return known ? double(occupied) / double(known) : 0.0; }
};

/** The cells of `outlines`' segments (sampled every quarter cell) in `grid`, whose map frame
 * is mapInWorld (world <- map); cells nearer than `keepOff` [m] to a segment of `other` (a wall
 * or an object present in the other session) are left out. A known cell counts as occupied
 * if it or a cell within `slack` cells of it (Chebyshev distance) is occupied: slack 1
 * forgives the map's own error of up to a cell. */
TOutlineCells outlineCells(const mrpt::maps::COccupancyGridMap2D& grid,
						   const mrpt::math::TPose2D& mapInWorld,
						   const CSyntheticWorld& outlines, const CSyntheticWorld& other,
						   double keepOff = 0.1, int slack = 0);

}  // namespace lrgc::test
