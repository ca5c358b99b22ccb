/* Pose uncertainty relative to a node, from the graph (LRGC paper section 2.4: loop closing
 * searches only old poses within a Mahalanobis distance of the current estimate, and that
 * search area grows with the robot's position uncertainty and shrinks after a loop closes).
 *
 * Method: Dijkstra from `source` over the enabled links, each link an independent Gaussian
 * relative measurement with covariance Omega^-1. Along a path the relative pose is composed
 * and its covariance propagated to first order (Smith, Self & Cheeseman compounding):
 *     T_sv = T_su (+) T_uv,   C_sv = J1 C_su J1^T + J2 C_uv J2^T
 *     J1 = [1 0 -(s x_uv + c y_uv); 0 1 (c x_uv - s y_uv); 0 0 1],  J2 = [R(phi_su) 0; 0 1]
 * (a link walked against its direction contributes the inverse pose, C = Ji C_l Ji^T).
 * The Jacobians are evaluated at the graph's current poses, so `nodeInSource` equals
 * between(pose(source), pose(node)) exactly. The priority is the position variance
 * trace(C_xy) [m^2]: each node keeps the covariance of the single most certain path found.
 *
 * What it approximates: the marginal covariance of X_source^-1 X_node under the linearised
 * graph with the source fixed. It ignores the information of every other path (parallel
 * paths, loops not on the chosen path) and correlations between them, so the result is an
 * over-estimate (conservative: search areas are too large rather than too small). On a tree
 * (no loops) it is exact to first order. Cost O((V + E) log V) for the V nodes and E links it
 * reaches, independent of the graph size when bounded by `maxNodes` or `maxPositionStd`.
 *
 * A step's model (TStepModel, the loop closer's gate; issue 28 item 1). With every link a path
 * of its own, a step between consecutive keyframes is walked by the link that places the node
 * with the smaller position variance: near the source the odometry link (a few cm, but
 * 1.7 deg), and the heading variance it brings compounds down the path: after one 392 m lap
 * of the glass atrium the start seen from the newest keyframe had a std of 24 / 50 m and
 * 33 deg where the online map was 0.4 m and 0.6 deg off. `fuseParallelLinks` walks each step
 * once, with the information of its parallel links added: per link type the one most certain
 * in position stands for the type (links of one type share their scans: a patch link and a
 * pairwise link match the same keyframe), and the types are independent sensors (odometry,
 * scan matching, loop links), so for the step u -> v
 *     C_uv = (sum over types t of C_t^-1)^-1 .
 * Scan matching's covariance holds no drift a match cannot see (a corridor's slide along
 * itself, a scale error): on MIT Killian the fused gate claimed 0.3 m where the return was
 * 1.9 m off along its corridor. `driftXY` adds it as a random walk in position per metre of
 * step, in the step's frame,
 *     C_uv += driftXY * |t_uv| * diag(1, 1, 0)   [m^2; t_uv the step's translation, m],
 * sized on the runs with truth (doc/generalisation.md, the glass_stress section).
 */
#pragma once

#include <mrpt/math/TPose2D.h>

#include <Eigen/Core>
#include <limits>
#include <vector>

#include <lrgc/pose_graph/PoseGraph.h>

namespace lrgc
{
struct TRelativeUncertainty
{
	size_t node = 0;
	mrpt::math::TPose2D nodeInSource;  //!< (source <- node) at the current estimate
	Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();  //!< of nodeInSource, (x, y, phi) [m, rad]
};

struct TUncertaintyLimits
{
	/** Stop after this many nodes (source included) have been reached (0: no limit). */
	size_t maxNodes = 0;
	/** Do not expand beyond a node whose position std sqrt(trace C_xy) exceeds this [m]
	 * (the node itself is returned). Bounds the search to where a loop could still be. */
	double maxPositionStd = std::numeric_limits<double>::infinity();
	/** Stop once this node is reached (it is then the last one returned). */
	size_t stopAtNode = std::numeric_limits<size_t>::max();
};

/** How one step of a path (a pair of linked nodes) is modelled; the defaults are the plain
 * single-link propagation (see the file comment). */
struct TStepModel
{
	/** Walk a step once, with its parallel links' information added per link type. */
	bool fuseParallelLinks = false;
	/** [m^2 per m of step] Position variance added to each step, in both axes of its frame. */
	double driftXY = 0;
};

/** Returns the source (zero covariance) and every reached node, in order of increasing
 * position variance. Throws if `source` is out of range. */
std::vector<TRelativeUncertainty> propagateUncertainty(const CPoseGraph& g, size_t source,
													   const TUncertaintyLimits& limits = {},
													   const TStepModel& model = {});

/** (source <- v) from (source <- a) and (a <- v) (`.node` is v): the pose composed and the
 * covariance compounded to first order, as one step of a path in propagateUncertainty. */
TRelativeUncertainty chainUncertainty(const TRelativeUncertainty& aInSource,
									  const TRelativeUncertainty& vInA);

/** Covariance of Z^-1 given that of Z = (x, y, phi), first order at Z:
 *     J = d(Z^-1)/dZ = [-c -s  s x - c y;  s -c  c x + s y;  0 0 -1],  C' = J C J^T. */
Eigen::Matrix3d inverseCovariance(const mrpt::math::TPose2D& z, const Eigen::Matrix3d& covZ);

/** Squared Mahalanobis distance of the node's position from the source's, using the xy block
 * of `cov`: (x, y) C_xy^-1 (x, y)^T [-], the loop-closing gate of paper section 2.4. A zero
 * offset gives 0; throws if C_xy is singular while the offset is not zero. */
double positionMahalanobis2(const TRelativeUncertainty& r);

}  // namespace lrgc
