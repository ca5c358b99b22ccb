/* SE(2) helpers on mrpt::math::TPose2D used across lrgc.
 *
 * Frames: a pose "bInA" maps coordinates of frame b into frame a: p_a = bInA (+) p_b.
 * Composition is MRPT's: (a + b) = a (+) b; (b - a) = a^-1 (+) b, i.e. "b in a".
 * Angles are radians, wrapped to (-pi, pi]. Distances are metres.
 */
#pragma once

#include <mrpt/math/TPoint2D.h>
#include <mrpt/math/TPose2D.h>
#include <mrpt/math/wrap2pi.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cmath>

namespace lrgc
{
using mrpt::math::TPose2D;

/** a (+) b, angle wrapped. */
inline TPose2D compose(const TPose2D& a, const TPose2D& b)
{
	const double c = std::cos(a.phi), s = std::sin(a.phi);
	return {a.x + c * b.x - s * b.y, a.y + s * b.x + c * b.y,
			mrpt::math::wrapToPi(a.phi + b.phi)};
}

/** a^-1 */
inline TPose2D inverse(const TPose2D& a)
{
	const double c = std::cos(a.phi), s = std::sin(a.phi);
	return {-c * a.x - s * a.y, s * a.x - c * a.y, mrpt::math::wrapToPi(-a.phi)};
}

/** a^-1 (+) b: the pose of b expressed in the frame of a ("b in a"). */
inline TPose2D between(const TPose2D& a, const TPose2D& b)
{
	const double c = std::cos(a.phi), s = std::sin(a.phi);
	const double dx = b.x - a.x, dy = b.y - a.y;
	return {c * dx + s * dy, -s * dx + c * dy, mrpt::math::wrapToPi(b.phi - a.phi)};
}

/** Applies pose to a point: R(phi) p + t. */
inline Eigen::Vector2d transformPoint(const TPose2D& pose, const Eigen::Vector2d& p)
{
	const double c = std::cos(pose.phi), s = std::sin(pose.phi);
	return {pose.x + c * p.x() - s * p.y(), pose.y + s * p.x() + c * p.y()};
}

/** transformPoint with the rotation computed once, for loops over the points of a scan. */
class CPointTransform
{
public:
	explicit CPointTransform(const TPose2D& pose)
		: m_x(pose.x), m_y(pose.y), m_c(std::cos(pose.phi)), m_s(std::sin(pose.phi))
	{
	}
	Eigen::Vector2d operator()(const Eigen::Vector2d& p) const
	{
		return {m_x + m_c * p.x() - m_s * p.y(), m_y + m_s * p.x() + m_c * p.y()};
	}

private:
	double m_x, m_y, m_c, m_s;
};

inline Eigen::Vector3d toVector(const TPose2D& p)
{
	return {p.x, p.y, p.phi};
}
inline TPose2D fromVector(const Eigen::Vector3d& v)
{
	return {v.x(), v.y(), mrpt::math::wrapToPi(v.z())};
}

/** A covariance over (x [m], y [m], phi [rad]) given in the axes of a frame at heading phi,
 * in the axes of its parent frame (the map's): R(phi) C R(phi)^T. With -phi, from the
 * parent's axes into the frame's. */
inline Eigen::Matrix3d rotateCovariance(const Eigen::Matrix3d& C, double phi)
{
	Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
	const double c = std::cos(phi), s = std::sin(phi);
	R.topLeftCorner<2, 2>() << c, -s, s, c;
	return R * C * R.transpose();
}

/** Translation norm [m]. */
inline double translationNorm(const TPose2D& p)
{
	return std::hypot(p.x, p.y);
}

/** An odometry step the wheels did not make: under 1 mm and 1 mrad (encoder ticks round to
 * zero). Local registration trusts it over a match that moves the robot; the scan smoothing
 * leaves it out of the odometry's calibration. */
inline bool isZeroStep(const TPose2D& motion)
{
	return translationNorm(motion) < 1e-3 && std::abs(motion.phi) < 1e-3;
}

/** Chi-square of the disagreement between two independent estimates of one relative pose:
 *     d = v(expected^-1 (+) measured),   chi2 = d^T C^-1 d   [-, 3 dof]
 * with C the sum of both covariances over (x [m], y [m], phi [rad]) in the frame the poses
 * are expressed in. The gates of local registration (odometry glitches) and of the revisit
 * sweep compare it with a chi-square quantile. */
inline double disagreementChi2(const TPose2D& expected, const TPose2D& measured,
							   const Eigen::Matrix3d& C)
{
	const Eigen::Vector3d d = toVector(between(expected, measured));
	return d.dot(C.ldlt().solve(d));
}

/** Proves disagreementChi2(expected, measured, A + B) <= gate for every positive
 * semidefinite B without B: (A + B)^-1 <= A^-1, so the chi2 under A alone bounds it from
 * above. The bound must lie below (1 - 1e-6) x the gate, so that the rounding of the two
 * LDLT solves (relative ~1e-16 times A's condition number) cannot decide otherwise than the
 * test with B, and A must be positive definite and far from singular (its LDLT pivots within
 * 1e9 of each other): a singular A's solve is no bound. False: not proven (B is needed).
 * A match's covariance B is costly (the noise model's walk, the jackknife) and most tests
 * agree: local registration's glitch test (A the prior's covariance, whose motion models are
 * diagonal with positive floors) and the revisit sweep's checks skip it where this proves
 * agreement. On the shared logs the bound's ratio to the gate was at most 0.9998 where it
 * proved agreement (ACES, MIT-CSAIL, the synthetic logs). */
inline bool agreesWhateverTheOtherCovariance(const TPose2D& expected, const TPose2D& measured,
											 const Eigen::Matrix3d& A, double gate)
{
	const Eigen::LDLT<Eigen::Matrix3d> ldlt(A);
	const Eigen::Vector3d D = ldlt.vectorD();
	if (ldlt.info() != Eigen::Success || !(D.minCoeff() > 0) ||
		!(D.minCoeff() > 1e-9 * D.maxCoeff()))
		return false;
	const Eigen::Vector3d d = toVector(between(expected, measured));
	return d.dot(ldlt.solve(d)) <= (1 - 1e-6) * gate;
}

}  // namespace lrgc
