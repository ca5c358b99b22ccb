/* The pose grid of global correlation (Gutmann & Konolige 2000, section 2.3;
 * PatchCorrelator.cpp has the steps of a query): its geometry, the base cells of a patch per
 * heading, and step 5, the best cluster's covariance from the response sampled around the best
 * pose. Frames: map (the correlation grid's); units: m, rad. Not installed (a detail of
 * PatchCorrelator.cpp).
 */
#pragma once

#include <lrgc/loop_closing/CorrelationGrid.h>
#include <lrgc/loop_closing/PatchCorrelatorParams.h>

#include <mrpt/math/TPose2D.h>
#include <mrpt/math/wrap2pi.h>

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace lrgc::detail
{
/** The pose grid over a window: pose (a, i, j) = (center.x + i res, center.y + j res,
 * theta(a)). */
struct TGridSpec
{
	mrpt::math::TPose2D center;
	double res = 0, dtheta = 0;
	int angle0 = 0;  //!< theta_a = center.phi + (a - angle0) dtheta
	double theta(int a) const { return center.phi + (a - angle0) * dtheta; }
	mrpt::math::TPose2D pose(int a, int i, int j) const
	{
		return {center.x + i * res, center.y + j * res, mrpt::math::wrapToPi(theta(a))};
	}
};

/** Base cells (cx, cy) of every point rotated by theta [rad] and moved by the window centre. */
void appendBaseCells(const CCorrelationGrid& grid, const std::vector<Eigen::Vector2d>& pts,
					 const mrpt::math::TPose2D& center, double theta,
					 std::vector<int32_t>& out);

/** Step 5: covariance of the best cluster at pose (a, i, j) of score bestScore: first the pose
 * grid's own lattice, +-4 steps; if the response is not contained in it (a std dev above a
 * third of its half-width), a coarser lattice spanning +-3 maxStd with at most 4 samples per
 * side. */
Eigen::Matrix3d clusterCovariance(const TPatchCorrelatorParams& prm,
								  const CCorrelationGrid& grid,
								  const std::vector<Eigen::Vector2d>& pts,
								  const TGridSpec& spec, int a, int i, int j,
								  int64_t bestScore);

}  // namespace lrgc::detail
