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
 * A one-reading glitch (the odometry of one pose reads tens of degrees more turn, the next
 * reading right again; or a step turning faster than the jump test allows, a sparse log's
 * turn in place between two scans) leaves that scan placed off its odometry: by the jump's
 * constant-velocity prior or by a wide search that overruled it; an unmatched jump keeps the
 * constant-velocity pose, up to 135 deg off. The next step's odometry then undoes the glitch
 * (or counts from the "new frame"), and composed onto the misplaced scan it predicts the next
 * scan just as far off: its match then fails, or the wide search settles on a rotated twin of
 * the place, and every later scan follows (the room world, a 135-175 deg turn in one step with
 * a one-pose glitch of 40-120 deg: 20 of 48 runs ended with every later scan 40-180 deg off).
 * So after a scan not placed where its odometry said, and at a jump, the prediction carries an
 * alternative: the odometry read since the last scan that was, composed onto that scan's
 * estimated pose and expressed from the last scan, with that odometry's noise. It is the
 * prediction itself when the odometry came back (one glitched reading) and is offered for
 * kAlternativeScans scans; the registration tries it when the prediction's match fails or
 * contradicts it and the alternative turns the robot otherwise by more than glitch_min_turn
 * (CLocalRegistration::registerScan).
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
/** The odometry since the last scan placed in agreement with it (see the file comment), as a
 * second hypothesis for a scan's motion. */
struct TOdometryAlternative
{
	mrpt::math::TPose2D motion;  //!< (lastScan <- newScan) in the last scan's robot frame
	Eigen::Matrix3d cov;         //!< of motion: odometryCov of the odometry it spans
};

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
	/** Where the last scan was not placed where its odometry said (an odometry jump, a wide
	 * search overruling it) or this step is a jump: the odometry read since the last scan
	 * that was (see the file comment). */
	std::optional<TOdometryAlternative> alternative;
};

/** `p` with its alternative taken as the prediction: odometry, no jump, no alternative. */
TMotionPrediction followingAlternative(const TMotionPrediction& p);

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
	 * Odometry read so far now counts from this scan. `followedOdometry`: the scan was placed
	 * where its odometry prior said, matched within the prior's gate or unmatched on it (not
	 * on a jump's constant-velocity prior, not overruled by a scan match); the next scans'
	 * alternative counts from the last such scan. */
	void commitScan(mrpt::Clock::time_point t, const mrpt::math::TPose2D& estimatedMotion,
					bool followedOdometry = true);

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
	/** (odom <- robot) at the last scan that followed its odometry (commitScan). */
	std::optional<mrpt::math::TPose2D> m_odomAtAgreed;
	/** (that scan <- last scan), as estimated, and the scans committed since it. */
	mrpt::math::TPose2D m_sinceAgreed{0, 0, 0};
	size_t m_scansSinceAgreed = 0;
	/** The alternative is offered up to this many scans after the last that followed its
	 * odometry (file comment). */
	static constexpr size_t kAlternativeScans = 2;
	std::optional<TOdometryAlternative> alternative(const TMotionPrediction& pred) const;
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
