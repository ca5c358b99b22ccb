/* CMotionPredictor: the prior for each new scan's pose (the "predict" step of LRGC's data
 * flow, paper fig. 6), from wheel odometry when the robot has it, else from a
 * constant-velocity model so that a laser alone can map.
 *
 * Odometry arrives either as increments (MRPT rawlog layout 1: CActionRobotMovement2D, the
 * motion (previous <- current) in the robot frame) or as absolute readings (layout 2 and
 * CARMEN: CObservationOdometry, (odom <- robot)). Either way the predictor keeps the odometry
 * pose at the last committed scan, and predicts the motion d = (lastScan <- newScan) with the
 * usual proportional noise model (Thrun et al., Probabilistic Robotics, 5.4):
 *   sigma_xy  = floor_xy  + k_xy_m_per_m * |t| + k_xy_m_per_rad * |dphi|      [m]
 *   sigma_phi = floor_phi + k_phi_rad_per_m * |t| + k_phi_rad_per_rad * |dphi|    [rad]
 * with |t| replaced by sqrt(L |t|) beyond L = noise_correlation_length_m: the model holds for
 * a keyframe step, while a long odometry-only stretch (scans skipped where the laser saw
 * nothing) is a chain of independent steps whose variances add. Linear growth there made a
 * 20 m blind hall 67 deg of heading std, for a true drift of 7 deg.
 * Odometry glitches (a step turning 60-85 deg wrongly) are not judged here: the local
 * registration detects them from the scan match and down-weights the link.
 *
 * Odometry jumps are: a step no robot drives between two scans, over dt [s] since the last,
 *     |t| > kJumpShift + kJumpSpeed dt   or   |dphi| > kJumpTurn + kJumpTurnRate dt,
 * is the odometry's frame changing (a reboot of the base restarts it at (0, 0, 0), a driver
 * re-bases it), not motion: the step is predicted by constant velocity instead (below), the
 * reading after it counting from the new frame, and flagged so that the registration
 * searches widely. Left to the odometry, the robot was placed where the jump put it (Intel
 * driven again after a restart: 62 m and 146 deg away) and mapped known ground a second time
 * there. The largest steps between two scans of the benchmark logs are 0.95 m and 61 deg
 * (MIT-CSAIL, ACES), and the glitch search covers turns up to 90 deg.
 *
 * Constant velocity (no odometry): the last step's motion d_last over its interval dt_last,
 * times this scan's interval dt: d = d_last * dt / dt_last (bridges dropped scans and
 * irregular logging, ACES: 0.07-0.32 s). Only on a regular scan clock: logged timestamps can
 * be jittered in bursts (Intel: 631 backward jumps up to 0.9 s, the file order being the
 * true order), and scaling by such intervals turns a 5 deg step into a 25 deg prediction. A
 * clock that ran backwards or took a step under kJitterFraction * T (T: median of the
 * positive intervals) within the last kClockSteps scans is taken as jittered, and the
 * prediction is then one step per scan (d = d_last).
 */
#pragma once

#include <lrgc/local_registration/MotionPredictorParams.h>
#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/core/Clock.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/math/TPose2D.h>

#include <Eigen/Core>
#include <deque>
#include <optional>

namespace lrgc
{
struct TMotionPrediction
{
	mrpt::math::TPose2D motion;  //!< (lastScan <- newScan) in the last scan's robot frame
	Eigen::Matrix3d cov = Eigen::Matrix3d::Identity();  //!< of motion (x, y, phi)
	bool fromOdometry = false;
	/** The odometry step was a jump (see the file comment): `motion` is the constant-velocity
	 * prediction instead, fromOdometry is false, `odometryStep` is the jump. */
	bool odometryJump = false;
	mrpt::math::TPose2D odometryStep{0, 0, 0};  //!< the odometry's step, where it jumped
	double stepSeconds = 0;  //!< time since the last committed scan [s] (0 if unknown)
};

class CMotionPredictor
{
public:
	explicit CMotionPredictor(const TMotionPredictorParams& p = {}) : m_params(p) {}

	/** Robot motion (previous <- current) in the robot frame, e.g. from a rawlog action. */
	void addOdometryIncrement(const mrpt::math::TPose2D& motion);
	/** Absolute odometry reading (odom <- robot). */
	void addOdometryAbsolute(const mrpt::math::TPose2D& robotInOdom);

	/** Prediction for a scan at time t, relative to the last committed scan. */
	TMotionPrediction predict(mrpt::Clock::time_point t) const;

	/** The scan at time t was placed; `estimatedMotion` is (lastScan <- scan) as estimated.
	 * Odometry read so far now counts from this scan. */
	void commitScan(mrpt::Clock::time_point t, const mrpt::math::TPose2D& estimatedMotion);

	bool hasOdometry() const { return m_odomNow.has_value(); }
	/** The latest odometry pose (odom <- robot), nullopt before any odometry. */
	const std::optional<mrpt::math::TPose2D>& odometryNow() const { return m_odomNow; }
	/** Covariance of an odometry motion d by the proportional noise model above. */
	Eigen::Matrix3d odometryCov(const mrpt::math::TPose2D& d) const;
	/** Covariance of one constant-velocity step. */
	Eigen::Matrix3d constantVelocityCov() const;
	/** Scan period T [s] (median of recent intervals), 0 before two scans. */
	double scanPeriod() const;
	/** Mean scan interval [s]: the span of the recent timestamps over their count, right on
	 * a jittered clock too (where the intervals within a burst are ~1 ms); 0 before two. */
	double meanScanPeriod() const;
	/** The recent scan timestamps are jittered (see the file comment). */
	bool clockJittered() const;
	const TMotionPredictorParams& params() const { return m_params; }

private:
	TMotionPredictorParams m_params;
	std::optional<mrpt::math::TPose2D> m_odomNow;     //!< latest (odom <- robot)
	std::optional<mrpt::math::TPose2D> m_odomAtScan;  //!< (odom <- robot) at the last scan
	std::optional<mrpt::Clock::time_point> m_lastScanTime;
	mrpt::math::TPose2D m_lastMotion{0, 0, 0};  //!< estimated motion of the last step
	std::deque<double> m_recentSteps;  //!< the last kClockSteps scan intervals [s], any sign
	static constexpr size_t kClockSteps = 50;
	/** Odometry jump thresholds (file comment): [m], [m/s], [rad], [rad/s]. */
	static constexpr double kJumpShift = 2.0, kJumpSpeed = 2.0;
	static constexpr double kJumpTurn = mrpt::DEG2RAD(100.0),
							kJumpTurnRate = mrpt::DEG2RAD(90.0);
	bool isJump(const mrpt::math::TPose2D& step, double dt) const;
	static constexpr double kJitterFraction = 0.3;
};

}  // namespace lrgc
