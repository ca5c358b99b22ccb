/* CScanMatcher: robust Gauss-Newton on combined point-to-line (Cox) and point-to-point
 * (Lu & Milios) residuals; see ScanMatcher.h for the method and ScanMatcherCovariance.cpp for
 * the covariance, ScanMatcher_wide.cpp for the wide search (matchWide).
 *
 * One iteration at pose x = (tx, ty, phi):
 *  1. associate: each scan point q_i = R(phi) p_i + t to its nearest reference anchor within
 *     the gate (exact search in CReferenceCloud);
 *  2. scale: s = max(min_residual_std_m, 1.4826 median |e|) [m] over all residual rows;
 *  3. weights: Cauchy w = 1 / (1 + |e|^2 / c^2), c = 2.3849 s (95% efficiency at Gaussian
 *     noise; an outlier's influence vanishes as 1/|e|);
 *  4. step: dx = -H^+ g, H = sum w J^T J, g = sum w J^T e, truncated along unobservable
 *     directions;
 *  5. gate <- clamp(4 c + |dx|, floor, gate): never grows, tracks the residual scale so the
 *     final pairs are the ones the noise explains.
 * Converged when the step is below 10 um (lever-arm scaled) and the gate has settled.
 */
#include <lrgc/scan_matching/ScanMatcher.h>
#include <lrgc/common/OrderStatistic.h>
#include <lrgc/common/se2.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/math/wrap2pi.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "ScanMatcherDetail.h"

namespace lrgc
{
using detail::TCorrespondence;

namespace
{
constexpr double kCauchy = 2.3849;  // Cauchy constant for 95% Gaussian efficiency
constexpr double kMadToSigma = 1.4826;
constexpr double kConvergedStep_m = 1e-5;
constexpr double kFreezeStep_m = 1e-3;

/** Residual and jacobians of scan point p against anchor a at pose x (R p precomputed in r). */
void linearise(const CReferenceCloud& ref, const Eigen::Vector2d& r, const Eigen::Vector3d& x,
			   TCorrespondence& k)
{
	const auto& a = ref.anchors()[k.anchor];
	const Eigen::Vector2d q(r.x() + x.x(), r.y() + x.y());
	k.anchorPos = a.pos;
	k.isLine = a.isLine;
	const Eigen::Vector2d d = q - a.pos;
	if (a.isLine)
	{
		k.e0 = a.normal.dot(d);
		k.J0 = {a.normal.x(), a.normal.y(), a.normal.x() * -r.y() + a.normal.y() * r.x()};
		k.tOff = a.normal.x() * d.y() - a.normal.y() * d.x();  // t = (-n_y, n_x)
		k.Jt = {-a.normal.y(), a.normal.x(), a.normal.dot(r)};
		k.normalVar = a.normalVar;
	}
	else
	{
		k.e0 = d.x(), k.e1 = d.y();
		k.varAnchor = a.samplingVar + ref.pointVariance(k.anchor);
		k.J0 = {1, 0, -r.y()};
		k.J1 = {0, 1, r.x()};
	}
}

/** Warm association: a scan point's last searched position q0 [m, in ref], the anchor found
 * there within the gate (-1: none) and a bound b [m] below which no other anchor was
 * (CReferenceCloud::nearestWithBound). At the point's next position q, every other anchor
 * is at least b - |q - q0| away (triangle inequality), so a new search would answer
 *   anchor j, if |q - a_j| < b - |q - q0|: j when |q - a_j| < gate, else none;
 *   none,     if b - |q - q0| >= gate (the gate never grows);
 * and these answers are taken without the search: the pairs are exactly a new search's.
 * Later iterations move the scan by millimetres against anchors ~ref_resolution_m apart,
 * so most points keep their anchor. */
struct TWarmEntry
{
	Eigen::Vector2d q0 = Eigen::Vector2d::Zero();
	double bound = -1;  //!< < 0: no search yet
	int anchor = -1;
};

/** Slack [m] on the warm test against the rounding of the distances (~1e-15 m). */
constexpr double kWarmSlack_m = 1e-9;

/** ref.nearest(q, gate), answered from w where the bound allows, else searched (refreshing
 * w). */
int warmNearest(const CReferenceCloud& ref, const Eigen::Vector2d& q, double gate,
				TWarmEntry& w)
{
	const double reach = w.bound - (q - w.q0).norm() - kWarmSlack_m;
	if (w.anchor >= 0 && reach > 0)
	{
		// The same squared distance and test as CAnchorGrid::nearest's.
		const double d2 = (ref.anchors()[w.anchor].pos - q).squaredNorm();
		if (d2 < reach * reach) return d2 < gate * gate ? w.anchor : -1;
	}
	else if (w.anchor < 0 && w.bound >= 0 && reach >= gate)
		return -1;
	w.q0 = q;
	w.anchor = ref.nearestWithBound(q, gate, &w.bound);
	return w.anchor;
}

/** Nearest-anchor association within the gate (frozen == false; warm: one entry per point,
 * kept between iterations), or re-linearisation of the pairs already in `out` at the new
 * pose (frozen == true). */
void associate(const CReferenceCloud& ref, const std::vector<Eigen::Vector2d>& pts,
			   const Eigen::Vector3d& x, double gate, bool frozen,
			   std::vector<TWarmEntry>& warm, std::vector<TCorrespondence>& out)
{
	const double c = std::cos(x.z()), s = std::sin(x.z());
	auto rot = [&](const Eigen::Vector2d& p)
	{ return Eigen::Vector2d(c * p.x() - s * p.y(), s * p.x() + c * p.y()); };
	if (frozen)
	{
		for (auto& k : out) linearise(ref, rot(pts[k.point]), x, k);
		return;
	}
	out.clear();
	warm.resize(pts.size());
	for (uint32_t i = 0; i < pts.size(); ++i)
	{
		const Eigen::Vector2d r = rot(pts[i]);
		const int j =
			warmNearest(ref, Eigen::Vector2d(r.x() + x.x(), r.y() + x.y()), gate, warm[i]);
		if (j < 0) continue;
		TCorrespondence k;
		k.anchor = static_cast<uint32_t>(j);
		k.point = i;
		linearise(ref, r, x, k);
		out.push_back(k);
	}
}

double robustScale(const std::vector<TCorrespondence>& corr, double floor,
				   std::vector<double>& tmp)
{
	tmp.clear();
	for (const auto& k : corr)
	{
		tmp.push_back(std::abs(k.e0));
		if (!k.isLine) tmp.push_back(std::abs(k.e1));
	}
	if (tmp.empty()) return floor;
	return std::max(floor, kMadToSigma * upperMedian(tmp));
}

/** Robust weights and the normal equations; returns the RMS lever arm L [m]. */
double weighAndAccumulate(std::vector<TCorrespondence>& corr, double scale,
						  Eigen::Matrix3d& Hout, Eigen::Vector3d& gOut,
						  Eigen::Matrix3d& HspurOut)
{
	const double c2 = (kCauchy * scale) * (kCauchy * scale), s2 = scale * scale;
	// Local sums, copied out at the end: sums behind the references would be stored and
	// reloaded at every correspondence (they may alias corr), the jacobians with them.
	Eigen::Matrix3d H = Eigen::Matrix3d::Zero(), Hspur = Eigen::Matrix3d::Zero();
	Eigen::Vector3d g = Eigen::Vector3d::Zero();
	double sw = 0, swl = 0;
	for (auto& k : corr)
	{
		// Heteroscedastic Cauchy: a residual of variance s^2 + v weighs s^2 / (s^2 + v).
		const double prec = s2 / (s2 + k.varAnchor);
		k.c2 = c2 / prec;
		k.w = prec / (1 + k.sqNorm() / k.c2);
		H.noalias() += k.w * k.J0 * k.J0.transpose();
		g += k.w * k.e0 * k.J0;
		Hspur.noalias() += (k.w * k.normalVar) * k.Jt * k.Jt.transpose();
		// Lever arm |R p| is the rotation jacobian's magnitude for a line (or point) residual.
		const double arm2 =
			k.isLine ? k.J0.z() * k.J0.z() : k.J0.z() * k.J0.z() + k.J1.z() * k.J1.z();
		if (!k.isLine)
		{
			H.noalias() += k.w * k.J1 * k.J1.transpose();
			g += k.w * k.e1 * k.J1;
		}
		sw += k.w;
		swl += k.w * arm2;
	}
	Hout = H, gOut = g, HspurOut = Hspur;
	return sw > 0 ? std::sqrt(swl / sw) : 1.0;
}
/** m.cov = detail::poseCovariance(ref, corr, info, c, cluster, unobservableStd), or with
 * `deferOn` (ref, shared) that same call on the same inputs later (m.deferredCov,
 * DeferredCovariance.h), m.cov NaN meanwhile. */
void setCovariance(TScanMatch& m, const CReferenceCloud& ref,
				   std::vector<TCorrespondence>&& corr, const detail::TScaledInfo& info,
				   double c, double cluster, double unobservableStd,
				   const std::shared_ptr<const CReferenceCloud>& deferOn)
{
	if (!deferOn)
	{
		m.cov = detail::poseCovariance(ref, corr, info, c, cluster, unobservableStd);
		return;
	}
	m.cov.setConstant(std::numeric_limits<double>::quiet_NaN());
	m.deferredCov = std::make_shared<CDeferredCovariance>(
		[ref = deferOn, corr = std::move(corr), info, c, cluster, u = unobservableStd]
		{ return detail::poseCovariance(*ref, corr, info, c, cluster, u); });
}
}  // namespace

namespace
{
/** The points a match of `scan` pairs: all of scan.points, or for a denoised scan
 * (TScan2D::matchStride k > 1) every k-th of them, copied into `strided`; k shrinks so that at
 * least 2 min_inliers points remain (a scan with few returns is matched whole). */
const std::vector<Eigen::Vector2d>& matchedPoints(const TScan2D& scan, int minInliers,
												  std::vector<Eigen::Vector2d>& strided)
{
	const size_t n = scan.points.size();
	const size_t k = std::min(scan.matchStride, n / (2 * static_cast<size_t>(minInliers)));
	if (k <= 1) return scan.points;
	strided.clear();
	strided.reserve(n / k + 1);
	for (size_t i = 0; i < n; i += k) strided.push_back(scan.points[i]);
	return strided;
}
}  // namespace

CScanMatcher::CScanMatcher(const TScanMatcherParams& p) : m_params(p)
{
	m_params.validate();
}

std::optional<TScanMatch> CScanMatcher::match(const CReferenceCloud& ref, const TScan2D& scan,
											  const mrpt::math::TPose2D& guess) const
{
	std::vector<Eigen::Vector2d> strided;
	return matchPoints(ref, matchedPoints(scan, m_params.min_inliers, strided), guess,
					   m_params.max_correspondence_dist_m, &scan);
}

std::optional<TScanMatch> CScanMatcher::matchDeferred(
	const std::shared_ptr<const CReferenceCloud>& ref, const TScan2D& scan,
	const mrpt::math::TPose2D& guess) const
{
	ASSERT_(ref);
	std::vector<Eigen::Vector2d> strided;
	return matchPoints(*ref, matchedPoints(scan, m_params.min_inliers, strided), guess,
					   m_params.max_correspondence_dist_m, &scan, ref);
}

namespace
{
/** [0..1] The refit of a loose fit must explain this much more of the scan (share of its
 * points within max_rms_residual_m of the reference) than the loose fit (refitLoose). On the
 * sparse logs a lead of 0.03 to 0.10 gives the same maps: two refits win there (leads 0.13
 * and 0.07, both moving the match onto the dense run's pose), the other loose fits' refits
 * explain -0.06 to +0.02 more. */
constexpr double kRefitLead = 0.05;
}  // namespace

TScanMatch CScanMatcher::refitLoose(const CReferenceCloud& ref, const TScan2D& scan,
									const TScanMatch& m,
									const std::shared_ptr<const CReferenceCloud>& deferOn) const
{
	ASSERT_(!deferOn || deferOn.get() == &ref);
	const double gate0 = m_params.max_correspondence_dist_m;
	const double inlierGate = rmsGate(scan.rangeNoiseStd);
	// Loose: the gate never shrank below its start (it shrinks to 4 c = 4 kCauchy s).
	if (4 * kCauchy * m.residualStd < gate0 || inlierGate >= gate0) return m;
	std::vector<Eigen::Vector2d> strided;
	const auto refit = matchPoints(ref, matchedPoints(scan, m_params.min_inliers, strided),
								   m.scanInRef, inlierGate, &scan, deferOn);
	if (refit && explainedFraction(ref, scan, refit->scanInRef) >=
					 explainedFraction(ref, scan, m.scanInRef) + kRefitLead)
		return *refit;
	return m;
}

double CScanMatcher::rmsGate(double scanNoiseStd) const
{
	return std::max(m_params.max_rms_residual_m, 3 * scanNoiseStd);
}

std::optional<TScanMatch> CScanMatcher::matchPoints(
	const CReferenceCloud& ref, const std::vector<Eigen::Vector2d>& pts,
	const mrpt::math::TPose2D& guess, double gate0, const TScan2D* checked,
	const std::shared_ptr<const CReferenceCloud>& deferOn) const
{
	const auto& P = m_params;
	if (ref.empty() || pts.size() < static_cast<size_t>(P.min_inliers)) return std::nullopt;
	Eigen::Vector3d x(guess.x, guess.y, guess.phi);
	double gate = gate0;
	const double gateFloor = std::max(5 * P.min_residual_std_m, 2 * P.ref_resolution_m);
	std::vector<TCorrespondence> corr;
	corr.reserve(pts.size());
	std::vector<TWarmEntry> warm;
	std::vector<double> tmp;
	Eigen::Matrix3d H, Hspur;
	Eigen::Vector3d g;
	bool converged = false, frozen = false;
	int it = 0;
	while (!converged && ++it <= P.max_iterations)
	{
		if (m_stop.stopRequested()) return std::nullopt;  // not converged: no match
		associate(ref, pts, x, gate, frozen, warm, corr);
		if (corr.size() < 3) return std::nullopt;
		const double scale = robustScale(corr, P.min_residual_std_m, tmp);
		const double L = weighAndAccumulate(corr, scale, H, g, Hspur);
		const auto info = detail::analyseInformation(H, Hspur, L, scale, P.unobservable_std_m);
		if (info.unobservable == 3) return std::nullopt;
		const Eigen::Vector3d dx = detail::solveStep(info, g);
		x += dx;
		const double step = dx.head<2>().norm() + L * std::abs(dx.z());
		const double newGate = std::clamp(4 * kCauchy * scale + step, gateFloor, gate);
		const bool settled = newGate > 0.99 * gate;
		converged = step < kConvergedStep_m && settled;
		// Nearest-anchor switches can make ICP cycle at the 0.1 mm level; once the gate has
		// settled and steps are sub-millimetre, keep the pairs and let Gauss-Newton converge.
		frozen = frozen || (settled && step < kFreezeStep_m);
		gate = newGate;
	}
	if (!converged) return std::nullopt;

	// Final linearisation at the solution, with the pairs it is optimal for: inliers,
	// residuals, covariance.
	associate(ref, pts, x, gate, frozen, warm, corr);
	if (corr.size() < 3) return std::nullopt;
	const double scale = robustScale(corr, P.min_residual_std_m, tmp);
	const double L = weighAndAccumulate(corr, scale, H, g, Hspur);
	const auto info = detail::analyseInformation(H, Hspur, L, scale, P.unobservable_std_m);
	size_t inliers = 0, rows = 0;
	double se2 = 0;
	for (const auto& k : corr)
		if (k.sqNorm() <= k.c2) ++inliers, se2 += k.sqNorm(), rows += k.isLine ? 1 : 2;
	TScanMatch m;
	m.scanInRef = mrpt::math::TPose2D(x.x(), x.y(), mrpt::math::wrapToPi(x.z()));
	m.inlierFraction = static_cast<double>(inliers) / pts.size();
	m.rmsResidual = rows ? std::sqrt(se2 / rows) : 0.0;
	m.residualStd = scale;
	m.iterations = it;
	m.unobservableDims = info.unobservable;
	// Unchecked (matchWide's alternatives): the converged pose and its inliers, no verdict.
	if (!checked) return m;
	if (inliers < static_cast<size_t>(P.min_inliers) ||
		m.inlierFraction < P.min_inlier_fraction ||
		m.rmsResidual > rmsGate(checked->rangeNoiseStd) || info.unobservable > 1)
		return std::nullopt;
	// Free-space consistency: aligned scan points must not sit where the reference saw through
	// (a violation is a share, never above 1: at max_free_space_violation 1 the check is off).
	if (P.max_free_space_violation < 1)
	{
		m.freeSpaceViolation =
			ref.freeSpaceViolation(*checked, m.scanInRef, freeSpaceMargin(scale),
								   m_freeSpaceParallel, P.free_space_min_run_m);
		if (m.freeSpaceViolation > P.max_free_space_violation) return std::nullopt;
	}
	// Residuals of anchors closer than this share reference noise (the line fit neighbourhood
	// is up to 4 normal_radius_m wide where sparse).
	const double cluster = std::max(0.5, 2 * P.normal_radius_m);
	setCovariance(m, ref, std::move(corr), info, kCauchy * scale, cluster, P.unobservable_std_m,
				  deferOn);
	return m;
}

}  // namespace lrgc
