/* CScanMatcher: pairwise 2D scan matching (paper section 2.1) returning the pose of a scan in
 * a reference (one scan or a local patch, see CReferenceCloud) and an honest covariance.
 *
 * Method: iteratively re-weighted Gauss-Newton on the combined Cox / Lu-Milios error, as in
 * Gutmann & Schlegel's combination the paper uses:
 *   LINE anchor (Cox, point-to-line):   e_i = n_j . (R(phi) p_i + t - a_j)            [m]
 *   POINT anchor (Lu-Milios, point):    e_i = R(phi) p_i + t - a_j  (2 rows)          [m]
 * with the nearest anchor j (exact, within a gate that shrinks to a few residual sigmas), a
 * Cauchy weight w_i = 1 / (1 + (e_i / (2.385 s))^2) whose scale s is re-estimated from the
 * residuals every iteration (1.4826 * median |e|), and a closed-form 3x3 solve per iteration;
 * once steps are sub-millimetre the pairs are frozen so that ICP cannot cycle.
 *
 * Covariance of (x, y, phi) in ref: M-estimator sandwich A^-1 M A^-1 (A from the Cauchy psi'),
 * whose meat M is the larger of (a) a noise model that propagates the reference's own noise
 * through its line fits, so residuals sharing a stretch of reference wall count as correlated,
 * and (b) a leave-one-cluster-out jackknife over reference cells, which measures correlation
 * from the data. Directions the data do not fix (a featureless corridor's axis: information
 * below s^2 / unobservable_std_m^2, or not clearly above what the normals' noise fakes) keep
 * the guess and get variance unobservable_std_m^2. Alignments that put either side's points in
 * space the other side saw empty are rejected. Measured NEES: doc/scan-matching.md.
 */
#pragma once

#include <lrgc/scan_matching/DeferredCovariance.h>
#include <lrgc/common/StopToken.h>
#include <lrgc/scan_matching/ScanMatcherParams.h>
#include <lrgc/scan_matching/ReferenceCloud.h>
#include <lrgc/scan_matching/Scan.h>
#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/math/TPose2D.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

namespace lrgc
{
struct TScanMatch
{
	mrpt::math::TPose2D scanInRef;  //!< (ref <- scan)
	/** Covariance of (x [m], y [m], phi [rad]) of scanInRef, in the ref frame. NaN where the
	 * match deferred it (deferredCov; CScanMatcher::matchDeferred): read covariance() then. */
	Eigen::Matrix3d cov = Eigen::Matrix3d::Identity();
	/** Non-null: cov is computed later, on whichever thread asks first (DeferredCovariance.h),
	 * shared by the match's copies. */
	std::shared_ptr<CDeferredCovariance> deferredCov;
	/** cov, or the deferred one (computed or waited for on get()). */
	CLazyCovariance covariance() const
	{
		return deferredCov ? CLazyCovariance(deferredCov) : CLazyCovariance(cov);
	}
	double inlierFraction = 0;  //!< inlier points / scan points
	/** Free-space inconsistency (CReferenceCloud::freeSpaceViolation): the share of points
	 * of either side lying where the other side's beams passed. A wrong alignment has many.
	 * 0 (not computed) where max_free_space_violation is 1 (the check off). */
	double freeSpaceViolation = 0;
	double rmsResidual = 0;  //!< [m] RMS of inlier residuals
	double residualStd = 0;  //!< [m] robust residual scale s at convergence
	int iterations = 0;
	/** Directions (0..1) the data leave free (corridor axis); cov is unobservable_std_m^2 there
	 * and scanInRef keeps the guess along them. */
	int unobservableDims = 0;
};

class CScanMatcher
{
public:
	/** Validates p (throws on bad values). */
	explicit CScanMatcher(const TScanMatcherParams& p = {});
	const TScanMatcherParams& params() const { return m_params; }
	/** Once `stop` is stopped, match() and matchWide() end before their next iteration or
	 * start and find nothing. */
	void setStopToken(const CStopToken& stop) { m_stop = stop; }
	/** A checked match's free-space test runs its parts by `parallel`
	 * (CReferenceCloud::freeSpaceViolation; the same value on any threads). It may be called
	 * from any thread matching, also from within another `parallel` loop. */
	void setFreeSpaceParallel(TParallelFor parallel)
	{
		m_freeSpaceParallel = std::move(parallel);
	}

	/** Local match from guessScanInRef (ref <- scan). nullopt: too few inliers, no convergence,
	 * RMS too large, or geometry degenerate in more than one direction. Never the guess.
	 * A denoised scan is matched on every TScan2D::matchStride-th point (its inlier fraction
	 * a share of those), its free-space check on all. */
	std::optional<TScanMatch> match(const CReferenceCloud& ref, const TScan2D& scan,
									const mrpt::math::TPose2D& guessScanInRef) const;
	/** match(), its covariance deferred (TScanMatch::deferredCov): computed from the same
	 * pairs by the same code when asked for, so the same bits. `ref` is shared because that
	 * computation reads it. */
	std::optional<TScanMatch> matchDeferred(const std::shared_ptr<const CReferenceCloud>& ref,
											const TScan2D& scan,
											const mrpt::math::TPose2D& guessScanInRef) const;

	/** `m`, a match of `scan` against `ref` (match()), refitted if it is a loose fit: one
	 * whose residual scale s kept the gate at max_correspondence_dist_m (4 * 2.385 s >= it).
	 * Where the scan sees much the reference does not (a robot turning into ground the patch
	 * has not seen), the unseen part's points pair with anchors up to that gate away,
	 * inflate s, and the fit settles as a compromise between them and the walls both sides
	 * share: sparse MIT-CSAIL, keyframe 335 at -43.0 deg (s 0.085 m, 41 % of the scan within
	 * max_rms_residual_m) where the robot turned -37.1 deg (s 0.012 m, 54 %), 6 deg off.
	 * The refit starts from m with the gate a match's inliers must keep (max_rms_residual_m,
	 * or 3x a noisy laser's noise) and wins if it explains kRefitLead (0.05) more of the scan
	 * (ScanMatcher.cpp); else m. With `deferOn` (ref, shared) the refit's covariance is
	 * deferred as matchDeferred's. */
	TScanMatch refitLoose(const CReferenceCloud& ref, const TScan2D& scan, const TScanMatch& m,
						  const std::shared_ptr<const CReferenceCloud>& deferOn = {}) const;

	/** For odometry glitches: starts match() from headings guess.phi + k * wide_search_step
	 * over [-searchAngle_rad, +searchAngle_rad] and returns the best converged match, refined
	 * with the whole scan, only with evidence that a symmetric or repetitive scene cannot
	 * fake: (1) its inlier fraction is at least wide_min_inlier_fraction; (2) it beats every
	 * distinct alternative start by wide_ambiguity_margin, counting the alternatives match()
	 * would reject (an aliased twin rejected for its free-space test is still a twin); (3) it
	 * beats by the same margin the local optimum from the guess itself (the hypothesis "the
	 * guess was right"), converged on the whole scan. Else nullopt.
	 * The starts are independent: `parallel`, if given, runs them (TParallelFor), with the
	 * same result as one after the other. `step_rad` > 0 replaces wide_search_step as the
	 * heading step between starts. `sharedHeading`, if given, is set to the best start's
	 * heading [rad] where (2) alone refuses it and every rival within the margin lies within
	 * half a step of that heading (the heading is clear, the position is not); else NaN. */
	std::optional<TScanMatch> matchWide(const CReferenceCloud& ref, const TScan2D& scan,
										const mrpt::math::TPose2D& guessScanInRef,
										double searchAngle_rad,
										const TParallelFor& parallel = {}, double step_rad = 0,
										double* sharedHeading = nullptr) const;

	/** [m] The margin of a match's free-space check (CReferenceCloud::freeSpaceViolation):
	 * 4 robust residual stds `residualStd` [m] of the match, at least 0.1 m. */
	static double freeSpaceMargin(double residualStd) { return std::max(0.1, 4 * residualStd); }

	/** Whether two poses are distinct hypotheses for matchWide (farther apart than 0.2 m or
	 * 3 deg), not one basin. */
	static bool distinctHypotheses(const mrpt::math::TPose2D& a, const mrpt::math::TPose2D& b);

	/** Share of the scan's points within max_rms_residual_m of a reference anchor at
	 * scanInRef: the score matchWide ranks its hypotheses by (test (3) above). */
	double explainedFraction(const CReferenceCloud& ref, const TScan2D& scan,
							 const mrpt::math::TPose2D& scanInRef) const;

private:
	/** Matches the points `pts` (scan frame) from `guess` with the gate starting at
	 * `initialGate` [m]. `checked`: the scan `pts` are the points of (all, or every
	 * TScan2D::matchStride-th), whose match is to
	 * pass match()'s checks (its range noise for the RMS gate, its range image for the
	 * free-space check) and get its covariance; null: unchecked, the converged pose and its
	 * inliers only (matchWide's starts on a subsample). `deferOn` (ref, shared): the
	 * covariance deferred (TScanMatch::deferredCov). */
	std::optional<TScanMatch> matchPoints(
		const CReferenceCloud& ref, const std::vector<Eigen::Vector2d>& pts,
		const mrpt::math::TPose2D& guess, double initialGate, const TScan2D* checked = nullptr,
		const std::shared_ptr<const CReferenceCloud>& deferOn = {}) const;
	/** The inlier RMS gate for a scan of range noise `scanNoiseStd` [m] (TScan2D::
	 * rangeNoiseStd): max(max_rms_residual_m, 3 scanNoiseStd). The point-to-line residual of
	 * two such scans is ~sqrt(2) scanNoiseStd, inliers reaching 2.4x that (Cauchy c).
	 * scanNoiseStd is 0 unless the laser is noisy (kNoisyLaserStd_m). */
	double rmsGate(double scanNoiseStd) const;

	TScanMatcherParams m_params;
	CStopToken m_stop;
	TParallelFor m_freeSpaceParallel;
};

}  // namespace lrgc
