/* The pose graph as a least-squares problem for other optimisers: MRPT's graph-slam, g2o.
 *
 * MRPT's .graph reader keeps one edge per node pair (CNetworkOfPoses::loadFromTextFile
 * collapses the others), while our graph links a keyframe to the same neighbour by odometry,
 * by its match against the window patch and by a pairwise match (SENA: 1074 links between
 * 748 pairs). And our final optimisation is robust: loop links weigh s^2 Omega (DCS,
 * PoseGraphOptimizer.h), disabled links nothing. A plain least-squares optimiser reproduces
 * our poses only from one edge per pair carrying what the optimum saw:
 *   - a disabled link is not written;
 *   - a LoopClosure link, with robust loop closures on, gets its effective information
 *     s^2 Omega at the current poses, s = min(1, 2 Phi / (Phi + chi2)). At a stationary point
 *     of the robust cost, d rho / d chi2 = s^2 makes its gradient that of the weighted least
 *     squares, so the optimum is the same;
 *   - links between the same two nodes a < b are turned to point a -> b (a link b -> a with
 *     Z, Omega becomes Z^-1 with Ad_Z^-T Omega Ad_Z^-1, Ad_Z = [R_z, (z.y, -z.x)^T; 0 0 1], the
 *     first-order map of its residual e' = -Ad_Z e), then fused by information:
 *         Omega = sum_k Omega_k,   Z = Z_1 (+) Omega^-1 sum_k Omega_k d_k,
 *         d_k = v(Z_1^-1 (+) Z_k)   [m, m, rad], angles relative to the first link Z_1,
 *     which to first order in the residuals leaves the sum of the pair's chi2 unchanged up
 *     to a constant (a pair's measurements agree to a few cm and degrees).
 * The poses are written as they are (VERTEX_SE2), node 0 fixed.
 */
#pragma once

#include <lrgc/pose_graph/PoseGraphOptimizerParams.h>
#include <lrgc/pose_graph/PoseGraph.h>
#include <mrpt/graphs/CNetworkOfPoses.h>

namespace lrgc
{
/** Nodes as VERTEX_SE2, enabled links as EDGE_SE2 with their own information; root = node 0.
 * Node ids are the indices. Write it with saveToTextFile(). The link type is not kept. (Kept
 * out of CPoseGraph, whose header every stage includes: MRPT's network header alone takes
 * 3.7 s to parse.) */
mrpt::graphs::CNetworkOfPoses2DInf toMrpt(const CPoseGraph& g);

/** From an MRPT network with node ids 0..n-1 (throws otherwise). The .graph format has no
 * link types: a link to == from + 1 becomes Odometry, any other `nonSequentialType`. */
CPoseGraph poseGraphFromMrpt(const mrpt::graphs::CNetworkOfPoses2DInf& net,
							 LinkType nonSequentialType = LinkType::LoopClosure);

/** One EDGE_SE2 per node pair, each the information-weighted fusion of the pair's enabled
 * links with the weights of the optimiser `params` (see the file comment). */
mrpt::graphs::CNetworkOfPoses2DInf toMrptLeastSquares(const CPoseGraph& g,
													  const TPoseGraphOptimizerParams& params);

}  // namespace lrgc
