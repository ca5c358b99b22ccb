/* Drives the whole map builder (CMetricMapBuilderLRGC) through a synthetic world, the way a
 * rawlog in the observations-only layout would: per step an absolute CObservationOdometry
 * (dead-reckoned from the noisy increments) and a CObservation2DRangeScan ray-cast from the
 * true pose, both with the step's timestamp. Then compares the builder's trajectory with the
 * ground truth.
 *
 * Frames: the builder's map frame is the robot frame of the first scan (node 0 at the
 * origin), so a pose estimate e_k corresponds to the world pose truePoses[0] (+) e_k.
 *
 * Typical use:
 *   auto world = makeRoomWorld(42);
 *   auto tr = makeTrajectory(waypoints, 0.1, TOdometryNoise{}, 7);
 *   CMetricMapBuilderLRGC builder(params);
 *   feedBuilder(builder, world, tr, TSyntheticRunOptions{});
 *   const auto err = trajectoryError(builder.trajectory(), tr.truePoses);
 */
#pragma once

#include <lrgc/map_builder/CMetricMapBuilderLRGC.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <string>
#include <utility>
#include <vector>

#include "synthetic_world.h"

namespace lrgc::test
{
/** A driver-like MRPT laser observation holding exactly the returns of `scan` (a TScan2D made
 * by simulateScan with the same `laser`): beams without a point are marked invalid. */
mrpt::obs::CObservation2DRangeScan::Ptr laserObservationFromScan(
	const lrgc::TScan2D& scan, const TLaserSimParams& laser, mrpt::Clock::time_point t,
	const std::string& label = "LASER");

struct TSyntheticRunOptions
{
	bool odometry = true;  //!< false: laser scans only (the builder's constant-velocity model)
	double scanPeriod = 0.2;  //!< [s] between steps
	TLaserSimParams laser;
	uint32_t laserSeed = 1;  //!< range noise, outliers, drops
	/** People walking through the scans (their positions at each step's time), or none. */
	const CCrowd* crowd = nullptr;
	/** Interleaved beams (SICK LMS in 0.25 deg mode, CARMEN ROBOTLASER start angles): scan k
	 * is rotated by (k mod beamOffsetCycle) * beamOffsetStep [rad] in the sensor frame, as
	 * a log's changing start angle rotates the beam fan. */
	double beamOffsetStep = 0;
	int beamOffsetCycle = 1;
	bool finish = true;            //!< false: feedBuilder leaves builder.finish() to the caller
	double firstStepTime = 1.6e9;  //!< [s] timestamp of step 0 (a later session: later)
};

/** Timestamp of step k of a synthetic run whose step 0 is at t0 [s]. */
mrpt::Clock::time_point syntheticStepTime(size_t k, double scanPeriod, double t0 = 1.6e9);

/** Feeds every step of `tr` to the builder (odometry from tr.odometryPoses, scans ray-cast at
 * tr.truePoses) and calls finish() (unless opt.finish is false). */
void feedBuilder(lrgc::CMetricMapBuilderLRGC& builder, const CSyntheticWorld& world,
				 const TTrajectory& tr, const TSyntheticRunOptions& opt);

/** Error of an estimated trajectory (map frame = first true pose's frame) against the truth,
 * one estimate per true pose. */
struct TTrajectoryError
{
	double maxXY = 0, rmsXY = 0;  //!< [m] position error
	double maxPhi = 0;            //!< [rad] absolute heading error
	double finalXY = 0;           //!< [m] position error of the last pose
	size_t worstIndex = 0;        //!< pose with the largest position error
};
TTrajectoryError trajectoryError(const std::vector<mrpt::math::TPose2D>& estimate,
								 const std::vector<mrpt::math::TPose2D>& truth);
TTrajectoryError trajectoryError(const lrgc::TTrajectory& estimate,
								 const std::vector<mrpt::math::TPose2D>& truth);

/** True pose of each keyframe of the builder, in its map frame (truePoses[0]^-1 (+) truth). */
std::vector<mrpt::math::TPose2D> trueKeyframePoses(
	const lrgc::CMetricMapBuilderLRGC& builder, const std::vector<mrpt::math::TPose2D>& truth);

/** The LoopClosure links of the builder's graph against the ground truth. A link is true if
 * its measurement agrees with the true relative pose within maxXY [m] and maxPhi [rad], or
 * if the disagreement d is within the link's own stated uncertainty, d^T Omega d <= 16.27
 * (chi2, 3 dof, p = 0.001): a scan match in a bare corridor reports a ~1 m std along the
 * corridor and keeps its guess there, which is honest, not false. */
struct TLoopLinkAudit
{
	size_t enabledTrue = 0, enabledFalse = 0;        //!< in the final map
	size_t disabledTrue = 0, disabledFalse = 0;      //!< rejected by the back-end
	double worstEnabledXY = 0, worstEnabledPhi = 0;  //!< [m], [rad] disagreement with truth
	double worstEnabledChi2 = 0;                     //!< d^T Omega d of the enabled links
	std::string firstEnabledFalse;  //!< "from -> to: ..." for the failure message
	std::vector<std::pair<size_t, size_t>> enabledTrueLinks;  //!< (from, to) keyframes
};
TLoopLinkAudit auditLoopLinks(const lrgc::CMetricMapBuilderLRGC& builder,
							  const std::vector<mrpt::math::TPose2D>& truth, double maxXY,
							  double maxPhi);

/** Recomputes tr.odometryPoses from tr.odometryIncrements (after a test edited them: a glitch,
 * wheel slip). */
void rebuildOdometryPoses(TTrajectory& tr);

/** Scale errors of the odometry: each increment turns `turnScale` times the true turn (a gyro's
 * scale error) and travels `travelScale` times the true translation (a wheel's), on top of
 * its noise; then the odometry poses are integrated again. */
void scaleOdometry(TTrajectory& tr, double turnScale, double travelScale);

/** The long-range SICK of issue 28's 80-minute log as the simulator models it, scans every
 * `scanPeriod` [s]: 181 beams over 180 deg out to `maxRange` [m], 1 cm range noise, 2 % of the
 * beams dropped and 0.5 % spurious, mixed pixels wherever a beam straddles an edge,
 * `maxRangeDropRate` of the far and grazing returns lost, and the four start angles of its
 * ROBOTLASER lines (0.25 deg apart). */
TSyntheticRunOptions longRangeSick(double scanPeriod, double maxRange, double maxRangeDropRate,
								   uint32_t laserSeed);

/** A rectangular ring corridor (an office floor around a central block): outer walls
 * (0,0)-(W,H), inner block (w,w)-(W-w,H-w), and `boxes` small boxes (0.3 m) against the
 * outer walls at seeded places, so that motion along a corridor is observable only near a
 * box or a corner. */
CSyntheticWorld makeRingCorridorWorld(double W, double H, double w, uint32_t seed, int boxes);

/** Smallest distance [m] from the polyline of `poses` to the world's segments. */
double minClearance(const CSyntheticWorld& world,
					const std::vector<mrpt::math::TPose2D>& poses);

}  // namespace lrgc::test
