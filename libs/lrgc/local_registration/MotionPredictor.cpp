#include <lrgc/local_registration/MotionPredictor.h>

#include <lrgc/common/OrderStatistic.h>
#include <lrgc/common/params_io.h>
#include <lrgc/common/se2.h>

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/system/datetime.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace lrgc
{
void CMotionPredictor::addOdometryIncrement(const mrpt::math::TPose2D& motion)
{
	m_odomNow = compose(m_odomNow.value_or(mrpt::math::TPose2D(0, 0, 0)), motion);
}

void CMotionPredictor::addOdometryAbsolute(const mrpt::math::TPose2D& robotInOdom)
{
	m_odomNow = robotInOdom;
}

Eigen::Matrix3d CMotionPredictor::odometryCov(const mrpt::math::TPose2D& d) const
{
	const auto& p = m_params;
	// Distance term: proportional up to the correlation length L, then a random walk of
	// independent L-long pieces (variance linear in distance): t_eff = t or sqrt(L t).
	const double d_m = translationNorm(d), a = std::abs(d.phi);
	const double L = p.noise_correlation_length_m;
	const double t = d_m <= L ? d_m : std::sqrt(L * d_m);
	const double sxy = p.sigma_floor_xy_m + p.k_xy_m_per_m * t + p.k_xy_m_per_rad * a;
	const double sphi = p.sigma_floor_phi + p.k_phi_rad_per_m * t + p.k_phi_rad_per_rad * a;
	return Eigen::Vector3d(sxy * sxy, sxy * sxy, sphi * sphi).asDiagonal();
}

TMotionPrediction CMotionPredictor::predict(mrpt::Clock::time_point t) const
{
	TMotionPrediction pred;
	if (m_lastScanTime)
		pred.stepSeconds = std::max(0.0, mrpt::system::timeDifference(*m_lastScanTime, t));
	if (m_params.use_odometry && m_odomNow && m_odomAtScan)
	{
		const mrpt::math::TPose2D step = between(*m_odomAtScan, *m_odomNow);
		if (!isJump(step, pred.stepSeconds))
		{
			pred.motion = step;
			pred.cov = odometryCov(pred.motion);
			pred.fromOdometry = true;
			pred.alternative = alternative(pred);
			return pred;
		}
		pred.odometryJump = true;  // the odometry's frame changed: constant velocity below
		pred.odometryStep = step;
	}
	// Constant velocity: the last step's motion over its interval, times this interval, on a
	// regular clock (bridges dropped scans, up to 5 of the last interval); one step per scan
	// on a jittered clock.
	double ratio = 1.0;
	if (m_lastScanTime && !m_recentSteps.empty() && !clockJittered())
	{
		const double last = m_recentSteps.back();
		const double dt = mrpt::system::timeDifference(*m_lastScanTime, t);
		if (last > 0 && dt > 0 && dt < 5 * last) ratio = dt / last;
	}
	pred.motion = {ratio * m_lastMotion.x, ratio * m_lastMotion.y, ratio * m_lastMotion.phi};
	pred.cov = constantVelocityCov();
	if (pred.odometryJump) pred.alternative = alternative(pred);
	return pred;
}

std::optional<TOdometryAlternative> CMotionPredictor::alternative(
	const TMotionPrediction& pred) const
{
	// Only where the last scan did not follow its odometry, or this step jumped; and not once
	// the scan that did lies kAlternativeScans back (a lasting offset of the odometry, a wheel
	// slip, is the prediction's case: the steps after it are right).
	if (!m_odomNow || !m_odomAtAgreed || m_scansSinceAgreed > kAlternativeScans ||
		(m_scansSinceAgreed == 0 && !pred.odometryJump))
		return std::nullopt;
	// (last <- new) = (agreed <- last)^-1 (+) (agreed <- new), the latter by the odometry.
	const mrpt::math::TPose2D odometry = between(*m_odomAtAgreed, *m_odomNow);
	return TOdometryAlternative{between(m_sinceAgreed, odometry), odometryCov(odometry)};
}

TMotionPrediction followingAlternative(const TMotionPrediction& p)
{
	ASSERT_(p.alternative.has_value());
	TMotionPrediction q = p;
	q.motion = p.alternative->motion;
	q.cov = p.alternative->cov;
	q.fromOdometry = true;
	q.odometryJump = false;
	q.odometryStep = mrpt::math::TPose2D(0, 0, 0);
	q.alternative.reset();
	return q;
}

bool CMotionPredictor::isJump(const mrpt::math::TPose2D& step, double dt) const
{
	return translationNorm(step) > kJumpShift + kJumpSpeed * dt ||
		   std::abs(step.phi) > kJumpTurn + kJumpTurnRate * dt;
}

Eigen::Matrix3d CMotionPredictor::constantVelocityCov() const
{
	const double sxy = m_params.cv_sigma_xy_m, sphi = m_params.cv_sigma_phi;
	return Eigen::Vector3d(sxy * sxy, sxy * sxy, sphi * sphi).asDiagonal();
}

double CMotionPredictor::scanPeriod() const
{
	std::vector<double> positive;
	for (const double dt : m_recentSteps)
		if (dt > 0) positive.push_back(dt);
	if (positive.empty()) return 0;
	return upperMedian(positive);
}

double CMotionPredictor::meanScanPeriod() const
{
	if (m_recentSteps.empty()) return 0;
	double span = 0;
	for (const double dt : m_recentSteps) span += dt;
	return std::max(0.0, span / double(m_recentSteps.size()));
}

bool CMotionPredictor::clockJittered() const
{
	const double T = scanPeriod();
	return std::any_of(m_recentSteps.begin(), m_recentSteps.end(),
					   [T](double dt) { return dt < kJitterFraction * T; });
}

void CMotionPredictor::commitScan(mrpt::Clock::time_point t,
								  const mrpt::math::TPose2D& estimatedMotion,
								  bool followedOdometry)
{
	if (m_odomNow && followedOdometry)
	{
		m_odomAtAgreed = m_odomNow;
		m_sinceAgreed = mrpt::math::TPose2D(0, 0, 0);
		m_scansSinceAgreed = 0;
	}
	else if (m_odomAtAgreed)
	{
		m_sinceAgreed = compose(m_sinceAgreed, estimatedMotion);
		++m_scansSinceAgreed;
	}
	if (m_lastScanTime)
	{
		m_recentSteps.push_back(mrpt::system::timeDifference(*m_lastScanTime, t));
		if (m_recentSteps.size() > kClockSteps) m_recentSteps.pop_front();
	}
	m_lastMotion = estimatedMotion;
	m_lastScanTime = t;
	if (m_odomNow) m_odomAtScan = m_odomNow;
}

}  // namespace lrgc
