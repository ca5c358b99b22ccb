/* Every scan's pose final (issue 28 item 4): a scan that is not a keyframe keeps the pose its
 * registration gave it, relative to its keyframe; no later link checks it. A registration
 * that people or a repetitive scene pulled into another basin leaves that scan (or two or
 * three in a row) off while the map and its neighbours are right: measured in a 70 x 45 m
 * hall with 25 people, 0.4 m off where the map's rmse is 3 cm.
 *
 * The check, at the end of the run, runs on the scans' final poses p_i [map frame] and the
 * odometry steps o_i = (i-1 <- i) [robot frame]. A run of at most kMaxRun scans a+1..b-1
 * between two scans a and b is isolated when
 *   - the odometry bridges a to b:  |v(p_b^-1 (+) p_a (+) o_{a+1} (+) ... (+) o_b)|_xy
 *     <= kBridgeGate (the neighbours agree with each other through the odometry), and
 *   - each scan of the run is off that chain by more than kOffGate and by more than
 *     kOffFactor times the bridge's disagreement.
 * Keyframes count as scans here: a registration that jumps by more than the keyframe distance
 * makes one (its node keeps its pose; its scan's pose in the trajectory is settled).
 * Its scans then take the odometry chain from a, the bridge's disagreement spread linearly
 * over the run (so the run ends on p_b). Only steps with odometry count.
 */
#pragma once

#include <mrpt/math/TPose2D.h>

#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace lrgc
{
/** One scan of the trajectory as the check sees it. */
struct TScanStep
{
	mrpt::math::TPose2D pose;          //!< final pose [map frame]
	mrpt::math::TPose2D odometryStep;  //!< (previous scan <- this scan) from odometry
	/** Modelled covariance of odometryStep (x [m], y [m], phi [rad]; previous scan's axes):
	 * ScanSmoothing.h. */
	Eigen::Matrix3d stepCov = Eigen::Matrix3d::Identity();
	/** Covariance of the registered pose relative to its keyframe window (map axes). */
	Eigen::Matrix3d poseCov = Eigen::Matrix3d::Zero();
	bool fromOdometry = false;  //!< odometryStep is odometry (not a constant-velocity guess)
	bool keyframe = false;  //!< a graph node (its node keeps its pose; the scan's is settled)
};

/** Poses of the isolated scans of `scans` (see above), as (index, corrected pose) pairs. */
std::vector<std::pair<size_t, mrpt::math::TPose2D>> settleIsolatedScans(
	const std::vector<TScanStep>& scans);

}  // namespace lrgc
