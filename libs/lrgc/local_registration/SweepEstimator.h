/* CSweepEstimator: the laser's sweep time (first beam to last) estimated online from the scans
 * of turns, for de-skewing (Scan.h: a scan taken turning at w rad/s spans w * sweep more or
 * less than its nominal aperture, and uncorrected that makes a clockwise heading drift at
 * every turn).
 *
 * Method. Beam i of a scan is measured at the fraction f_i in [-1/2, 1/2] of the sweep, so a
 * scan de-skewed with a wrong sweep time keeps a residual angular skew: each point is off by
 * the rotation f_i * s about the robot, s = w tau - phi_applied [rad], tau the true sweep
 * time, phi_applied the turn the de-skewing took out. Two scans taken at the same turn rate
 * are skewed alike, and a skew common to both only biases their relative heading (the drift
 * above) without any misfit; what a match can see is the difference. So each scan i is
 * matched (fitSkew: point-to-line Gauss-Newton over x, y, phi and the skew s, Cauchy
 * weights) against the recent scan r whose turn rate differs most (by at least
 * min_rate_change_per_s), which gives the relative skew s_ir = s_i - s_r, and
 *     y = s_ir + phi_applied_i - phi_applied_r = tau (w_i - w_r) = tau x.
 * Turn rates w are those of the de-skewing (the predicted step over its time). tau is the
 * robust (Cauchy) regression of y on x through the origin over all pairs so far, minimised
 * on a grid of sweep times in [0, max_sweep_time_s] whose losses are accumulated pair by pair
 * (constant cost per scan, no look-ahead, the same result for the same input). Its standard
 * error is the sandwich formula over the (capped) list of pairs. The estimate is used once
 * there are min_samples pairs and the standard error is below max_std_s; before (no turns
 * yet), the sweep time is 0: no de-skewing.
 *
 * Cost: at most one reference cloud (one scan, ~0.2 ms) and one fit (~0.1 ms) per scan, and
 * only for scans whose turn rate changed. Frames: the scans' poses are chained from the
 * registered steps (a loop closure's correction does not reach them), in the robot frame of
 * the first scan.
 */
#pragma once

#include <lrgc/scan_matching/ReferenceCloud.h>
#include <lrgc/local_registration/SweepEstimatorParams.h>
#include <lrgc/scan_matching/Scan.h>
#include <lrgc/scan_matching/ScanMatcherParams.h>

#include <deque>
#include <memory>
#include <optional>
#include <vector>

namespace lrgc
{
/** A scan's pose and residual angular skew relative to a reference scan. */
struct TSkewFit
{
	mrpt::math::TPose2D scanInRef;  //!< (ref <- scan)
	double skew = 0;  //!< [rad] rotation over the sweep (first to last beam) still in the scan
	double skewStd = 0;  //!< [rad] its standard deviation (from the fit's information)
	size_t inliers = 0;  //!< points matched to a line within the Cauchy width
};

/** Fits `scan` (fractions[i]: sweep fraction of point i, Scan.h sweepFractions) to the line
 * anchors of `ref` from `guess` (ref <- scan), with the extra de-skewing rotation
 * R(f_i skew) of each point about the robot. nullopt if too few points match. */
std::optional<TSkewFit> fitSkew(const CReferenceCloud& ref, const TScan2D& scan,
								const std::vector<float>& fractions,
								const mrpt::math::TPose2D& guess);

/** What the estimator knows, for stats.json and logs. */
struct TSweepEstimate
{
	double sweepTime = 0;    //!< [s] in use for the next scan
	bool estimated = false;  //!< sweepTime comes from the scans (else fixed, or 0)
	double estimate = 0;     //!< [s] latest estimate (used or not yet), 0 before any pair
	double std = 0;          //!< [s] its standard error (0 before min_samples pairs)
	size_t samples = 0;      //!< scan pairs compared
};

class CSweepEstimator
{
public:
	/** fixedSweepTime > 0 ([MapBuilder] scan_sweep_time_s), or p.enabled false: that value is
	 * used throughout and nothing is estimated. */
	CSweepEstimator(const TSweepEstimatorParams& p, const TScanMatcherParams& matcher,
					double fixedSweepTime);

	/** [s] sweep time to de-skew the next scan with. */
	double sweepTime() const { return m_summary.sweepTime; }
	const TSweepEstimate& summary() const { return m_summary; }

	/** One scan as converted (`obs` -> `scan`, de-skewed by appliedTurn [rad] over the
	 * sweep) while turning at turnRate [rad/s]; `step` (previous scan <- this one) as
	 * registered, `matched` false if registration kept the prediction. */
	void observe(const mrpt::obs::CObservation2DRangeScan& obs, const TScan2D& scan,
				 double turnRate, double appliedTurn, const mrpt::math::TPose2D& step,
				 bool matched);

	/** A new log from the same laser (a new session on a saved map): the estimate stays,
	 * the recent scans are dropped (their poses are of the other log). */
	void startNewLog() { m_recent.clear(); }

	/** One pair (x = w_i - w_r [rad/s], y [rad], std of y [rad]); observe() calls it. */
	void addSample(double x, double y, double std);

private:
	struct TRecent
	{
		TScan2D scan;
		std::vector<float> fractions;
		mrpt::math::TPose2D pose;  //!< chained from the registered steps
		double turnRate = 0, appliedTurn = 0;
		bool matched = false;
		std::shared_ptr<const CReferenceCloud> cloud;  //!< built when first compared with
	};
	struct TSample
	{
		double x, y, std;
	};
	TRecent* referenceFor(const TRecent& cur);
	void updateEstimate();

	TSweepEstimatorParams m_params;
	TScanMatcherParams m_matcher;
	bool m_fixed = false;
	TSweepEstimate m_summary;
	mrpt::math::TPose2D m_pose{0, 0, 0};
	std::deque<TRecent> m_recent;
	std::vector<double> m_loss;      //!< Cauchy loss of the pairs at each grid sweep time
	std::vector<TSample> m_samples;  //!< the newest pairs, for the standard error
	size_t m_nextSample = 0;         //!< where the next pair goes once m_samples is full
};

}  // namespace lrgc
