/* Absolute and relative trajectory error against a ground-truth trajectory (for example the
 * exact `t x y phi` ground truth of MRPT's synthetic rawlogs).
 *
 * ATE: each ground-truth pose g_i (at time t_i) is paired with the estimate p_i = x(t_i)
 * (exact timestamp match or interpolation, CTrajectory2D::poseAt). The estimate is then moved
 * by the rigid SE(2) transform T = (R(theta), t) that minimises sum_i |R p_i + t - g_i|^2
 * (closed form, no scale; Horn/Umeyama in 2D, with centred points p'_i, g'_i):
 *   theta = atan2( sum g'_y p'_x - g'_x p'_y , sum g'_x p'_x + g'_y p'_y ),
 *   t     = mean(g) - R(theta) mean(p).
 * Errors: |R p_i + t - g_i| [m] and |wrap(phi_p + theta - phi_g)| [deg].
 *
 * RPE: the relation metric (relation_metric.h) with relations taken from the ground truth,
 * either between consecutive ground-truth poses (1 step) or from each pose to the first later
 * one at least a given path length away (fixed distance).
 */
#pragma once

#include <lrgc_apps/eval/relation_metric.h>
#include <lrgc_apps/eval/trajectory.h>

#include <cstddef>
#include <vector>

namespace lrgc::apps::eval
{
struct TAbsoluteTrajectoryError
{
	/** The best-fit transform applied to the estimate: (ground-truth frame <- estimate frame).
	 */
	mrpt::math::TPose2D alignment;
	TErrorStats trans_m;      //!< |R p_i + t - g_i| [m]
	TErrorStats rot_deg;      //!< heading error after alignment [deg]
	std::size_t matched = 0;  //!< ground-truth poses paired with an estimate
	/** Indices (into groundTruth.poses()) of poses outside the estimate's time span. */
	std::vector<std::size_t> unmatchedGroundTruth;
};

/** Best-fit rigid SE(2) transform T minimising sum |T(from_i) - to_i|^2 over point pairs
 * (x, y only). Needs at least one pair; with one pair, or all points coincident, only the
 * translation is determined and theta = 0. */
mrpt::math::TPose2D bestFitRigid2D(const std::vector<mrpt::math::TPose2D>& from,
								   const std::vector<mrpt::math::TPose2D>& to);

/** ATE of `estimate` against `groundTruth`. Throws if no ground-truth pose can be paired. */
TAbsoluteTrajectoryError evaluateAte(const CTrajectory2D& estimate,
									 const CTrajectory2D& groundTruth,
									 double exactTolerance_s = 1e-5);

/** Relations between ground-truth poses `step` apart in file order (step >= 1). */
std::vector<TRelation> relationsOverSteps(const CTrajectory2D& groundTruth, std::size_t step);

/** Relations from each ground-truth pose i to the first later pose j whose travelled path
 * length from i (sum of |translation| between consecutive poses) is >= distance_m. */
std::vector<TRelation> relationsOverDistance(const CTrajectory2D& groundTruth,
											 double distance_m);

}  // namespace lrgc::apps::eval
