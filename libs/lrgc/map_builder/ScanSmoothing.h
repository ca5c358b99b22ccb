/* Every scan's pose final, step 2 (issue 28 item 4): after the final optimisation and the
 * isolated runs (IsolatedScans.h), each scan that is not a keyframe is placed consistently
 * with the keyframes before and after it and with the odometry between them.
 *
 * A scan's registration alone placed it against the window of its time, with covariance
 * P_k (the patch match's, widened where the scan's returns are sparse as a lone patch
 * link's: lonePatchLinkCov, LocalRegistration.h); its neighbours' odometry says where it is
 * too, and once the graph is final the two keyframes around a run of scans are the
 * best-known poses. For each maximal run a+1..b-1 of scans that are not keyframes (a, b: the
 * keyframe scans around it, held fixed), the poses x_k minimise, by Gauss-Newton on SE(2),
 *     sum_k (x_k - p_k)^T P_k^-1 (x_k - p_k)                       registration [map axes]
 *   + sum_k w_k e_k^T (D Q_k D)^-1 e_k,  e_k = v(o_k^-1 (+) (x_{k-1}^-1 (+) x_k))   odometry
 * over the steps with odometry (o_k, its modelled covariance Q_k in the previous scan's axes).
 * D = diag(s_x, s_y, s_phi) calibrates the model on the run itself, per component c: for
 * every step with odometry, e_i = v(o_i^-1 (+) (p_{i-1}^-1 (+) p_i)) and
 *     s_c^2 = median_i(e_{i,c}^2 / Q_{i,cc}) / 0.4549   (the median of chi2 with 1 dof):
 * the model's shape, the spread the registered steps show (the model is deliberately loose,
 * for matching; the median ignores outliers while they are fewer than half). w_k = min(1, g /
 * chi2_k) with chi2_k = e_k^T (D Q_k D)^-1 e_k and g the 99 % quantile of chi2 with 3 dof
 * (Huber's weights): a step the odometry got wrong beyond its spread (a slip, an unflagged
 * glitch) pulls no harder than one at the gate. The weights are taken anew at each Gauss-Newton
 * step, at the current poses (iteratively reweighted least squares; the first step's are at the
 * registered poses): taken once at the registered poses, the two steps into and out of a scan
 * whose registration is off look like outliers themselves and the wrong registration keeps
 * most of its error (CrowdedHall, trajectory seed 44: scans after a corner 0.10-0.12 m off
 * while their keyframes are within 0.04 m; lap 1's worst scan 0.076 m with the weights taken
 * once, 0.057 m taken anew). A scan whose registration is
 * uncertain where its odometry is sure (turning in place among people) follows the
 * odometry; one the registration pins down keeps its pose.
 * Only the positions are taken; each scan keeps its registered heading. Taking the smoothed
 * headings too cost the benchmark logs' relations 25-150 % in rotation (ACES 0.30 -> 0.38
 * deg, MIT-CSAIL 0.32 -> 0.42 deg with the calibration per component; the odometry's heading
 * between two scans is worse there than its spread over the run says).
 */
#pragma once

#include <lrgc/map_builder/IsolatedScans.h>

#include <vector>

namespace lrgc
{
/** D = (s_x, s_y, s_phi) above (ones with fewer than 20 steps with odometry). */
Eigen::Vector3d odometryNoiseScale(const std::vector<TScanStep>& scans);

/** The smoothed poses of the scans of `scans` that are not keyframes (see above), as
 * (index, pose) pairs. `scale`: D (odometryNoiseScale). */
std::vector<std::pair<size_t, mrpt::math::TPose2D>> smoothScans(
	const std::vector<TScanStep>& scans, const Eigen::Vector3d& scale);

}  // namespace lrgc
