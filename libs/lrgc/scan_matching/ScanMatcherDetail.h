/* Internals of CScanMatcher shared by ScanMatcher.cpp and ScanMatcherCovariance.cpp (not a
 * public header). */
#pragma once

#include <lrgc/scan_matching/ReferenceCloud.h>

#include <Eigen/Core>
#include <vector>

namespace lrgc::detail
{
/** One correspondence: scan point -> reference anchor, linearised at the current pose.
 * LINE anchor: 1 residual row e0 = n . (q - a), jacobian J0 = [n_x, n_y, n . perp(q - t)].
 * POINT anchor: 2 rows (e0, e1) = q - a, J0 = [1, 0, -(q - t)_y], J1 = [0, 1, (q - t)_x].
 * Here q = R(phi) p + t is the scan point in ref and perp(v) = (-v_y, v_x) = dR/dphi p. */
struct TCorrespondence
{
	Eigen::Vector3d J0, J1;
	double e0 = 0, e1 = 0;
	double w = 1;  //!< robust weight
	/** POINT: variance of the anchor per axis [m^2] (noise / count + sampling); residual
	 * weight is scaled by s^2 / (s^2 + varAnchor), the Cauchy width by its inverse. */
	double varAnchor = 0;
	double c2 = 0;              //!< squared Cauchy width used for this residual [m^2]
	Eigen::Vector2d anchorPos;  //!< for clustering correlated residuals
	bool isLine = true;
	uint32_t anchor = 0;  //!< index in the reference cloud
	uint32_t point = 0;   //!< index in the scan
	double tOff = 0;  //!< LINE: tangential offset t . (q - a) [m] of the point from the anchor
	/** LINE: change of J0 per radian of normal tilt, [-n_y, n_x, n . R p], and the tilt's
	 * variance [rad^2]: a noisy normal fakes information along the line (corridor axis). */
	Eigen::Vector3d Jt = Eigen::Vector3d::Zero();
	double normalVar = 0;
	double sqNorm() const { return isLine ? e0 * e0 : e0 * e0 + e1 * e1; }
};

/** Pose x = (tx, ty, phi) solved in scaled coordinates (tx, ty, L phi) with L the lever arm
 * [m], so eigenvalues of the information are comparable in m^-2. */
struct TScaledInfo
{
	Eigen::Matrix3d V;       //!< eigenvectors (columns) of the scaled information
	Eigen::Vector3d lambda;  //!< eigenvalues, ascending [m^-2]
	bool observable[3] = {true, true, true};
	int unobservable = 0;
	double L = 1;        //!< lever arm [m]
	double minInfo = 0;  //!< observability threshold s^2 / unobservableStd^2 [m^-2]
};

/** Gauss-Newton step (scaled truncated eigen-solve): no motion along directions with
 * information lambda_k < s^2 / unobservableStd^2, or less than kSpurious times what the
 * normals' noise alone would fake there (Hspurious = sum w normalVar Jt Jt^T). */
TScaledInfo analyseInformation(const Eigen::Matrix3d& H, const Eigen::Matrix3d& Hspurious,
							   double L, double scale, double unobservableStd);
Eigen::Vector3d solveStep(const TScaledInfo& I, const Eigen::Vector3d& g);

/** A POINT correspondence's bread term: the Cauchy psi(e) = w e's derivative
 * d psi / d e = w I - 2 w^2 e e^T / c^2 (w = 1 / (1 + |e|^2 / c^2), e [m], c2 = c^2 [m^2]),
 * floored to PSD. Across e its eigenvalue is w; along e it is w (1 - 2 w |e|^2 / c^2), the
 * only one that can be negative (|e| > c): floored at 0, the term is w (I - u u^T), u = e /
 * |e|. */
Eigen::Matrix2d cauchyPointBread(double w, const Eigen::Vector2d& e, double c2);

/** Covariance of (tx, ty, phi): cluster-robust sandwich, bounded below by the i.i.d. model,
 * unobservableStd^2 along unobservable directions. `cluster` [m] is the side of the reference
 * cells whose residuals are treated as correlated. */
Eigen::Matrix3d poseCovariance(const CReferenceCloud& ref,
							   const std::vector<TCorrespondence>& corr, const TScaledInfo& I,
							   double cauchyC, double cluster, double unobservableStd);

}  // namespace lrgc::detail
