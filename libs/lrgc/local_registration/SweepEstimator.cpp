#include <lrgc/local_registration/SweepEstimator.h>

#include <lrgc/common/OrderStatistic.h>
#include <lrgc/common/se2.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace lrgc
{
using mrpt::math::TPose2D;

namespace
{
constexpr double kCauchy = 2.385;          // Cauchy width in residual scales (95 % efficiency)
constexpr size_t kRecentScans = 10;        // scans a new one may be compared with
constexpr double kMaxPairDistance = 1.0;   // [m] ... if this close
constexpr double kMaxPairTurn = M_PI / 4;  // [rad] ... and turned this little
constexpr size_t kGridSteps = 400;    // sweep times tried: max_sweep_time_s / kGridSteps apart
constexpr size_t kMaxSamples = 5000;  // newest pairs kept for the standard error
constexpr size_t kMinInliers = 40;
// A rate change beyond this is a clock glitch, not a robot (Intel's jitter bursts: 6.7 rad/s).
constexpr double kMaxRateChange = 3.0;  // [rad/s]
// The fit's skew std is optimistic (residuals along one wall are correlated): the pairs'
// residuals about the regression are 2.0-3.7 of it (ACES, MIT-CSAIL, Intel).
constexpr double kStdInflation = 3.0;

/** Robust scale of residuals e [m]: 1.4826 median |e|, floored. */
double robustScale(std::vector<double>& absResiduals, double floor)
{
	if (absResiduals.empty()) return floor;
	return std::max(floor, 1.4826 * upperMedian(absResiduals));
}
}  // namespace

// Gauss-Newton over v = (tx, ty, phi, s) [m, m, rad, rad]. Point i in the reference frame:
//     q_i = R(phi) R(f_i s) p_i + t,
// residual to its nearest LINE anchor (a, n):  e_i = n . (q_i - a)  [m], with jacobian
//     de/dt = n,  de/dphi = n . J (q_i - t),  de/ds = f_i n . J (q_i - t),  J = rot(90 deg).
// Cauchy weights w = 1 / (1 + (e / (c sigma))^2), sigma = 1.4826 median|e| re-estimated each
// iteration; the gate shrinks from 0.3 m to 4 c sigma. Std of s: sigma sqrt((A^-1)_ss),
// A = sum w J J^T (optimistic: residuals along one wall are correlated; the regression's
// robust standard error does not rely on it).
std::optional<TSkewFit> fitSkew(const CReferenceCloud& ref, const TScan2D& scan,
								const std::vector<float>& fractions, const TPose2D& guess)
{
	ASSERT_EQUAL_(scan.points.size(), fractions.size());
	Eigen::Vector4d v(guess.x, guess.y, guess.phi, 0.0);
	double sigma = 0.05, gate = 0.3;
	Eigen::Matrix4d A = Eigen::Matrix4d::Zero();
	size_t inliers = 0;
	std::vector<double> absResiduals;
	for (int it = 0; it < 30; ++it)
	{
		A.setZero();
		Eigen::Vector4d b = Eigen::Vector4d::Zero();
		absResiduals.clear();
		inliers = 0;
		const double c = std::cos(v[2]), sn = std::sin(v[2]);
		for (size_t i = 0; i < scan.points.size(); ++i)
		{
			const double f = fractions[i];
			const double cf = std::cos(f * v[3]), sf = std::sin(f * v[3]);
			const Eigen::Vector2d& p = scan.points[i];
			const Eigen::Vector2d pr(cf * p.x() - sf * p.y(), sf * p.x() + cf * p.y());
			const Eigen::Vector2d qt(c * pr.x() - sn * pr.y(), sn * pr.x() + c * pr.y());
			const Eigen::Vector2d q = qt + v.head<2>();
			const int k = ref.nearest(q, gate);
			if (k < 0) continue;
			const auto& a = ref.anchors()[size_t(k)];
			if (!a.isLine) continue;
			const double e = a.normal.dot(q - a.pos);
			const double dphi = -a.normal.x() * qt.y() + a.normal.y() * qt.x();
			const Eigen::Vector4d Jrow(a.normal.x(), a.normal.y(), dphi, f * dphi);
			const double u = e / (kCauchy * sigma), w = 1.0 / (1.0 + u * u);
			A += w * Jrow * Jrow.transpose();
			b += w * e * Jrow;
			absResiduals.push_back(std::abs(e));
			if (std::abs(e) < kCauchy * sigma) ++inliers;
		}
		if (absResiduals.size() < kMinInliers) return std::nullopt;
		const Eigen::Vector4d dv = A.ldlt().solve(-b);
		if (!dv.allFinite()) return std::nullopt;
		v += dv;
		sigma = robustScale(absResiduals, 0.003);
		const double newGate = std::max(0.05, std::min(gate, 4 * kCauchy * sigma));
		const bool settled = newGate == gate;
		gate = newGate;
		if (settled && dv.head<2>().norm() < 1e-5 && std::abs(dv[2]) < 1e-6 &&
			std::abs(dv[3]) < 1e-6)
			break;
	}
	if (inliers < kMinInliers || inliers < scan.points.size() / 3) return std::nullopt;
	const Eigen::Matrix4d cov = A.inverse();
	if (!cov.allFinite() || cov(3, 3) <= 0) return std::nullopt;
	TSkewFit fit;
	fit.scanInRef = TPose2D(v[0], v[1], mrpt::math::wrapToPi(v[2]));
	fit.skew = v[3];
	fit.skewStd = sigma * std::sqrt(cov(3, 3));
	fit.inliers = inliers;
	return fit;
}

CSweepEstimator::CSweepEstimator(const TSweepEstimatorParams& p,
								 const TScanMatcherParams& matcher, double fixedSweepTime)
	: m_params(p), m_matcher(matcher)
{
	m_fixed = fixedSweepTime > 0 || !p.enabled;
	m_summary.sweepTime = fixedSweepTime;
	if (!m_fixed) m_loss.assign(kGridSteps + 1, 0.0);
}

void CSweepEstimator::observe(const mrpt::obs::CObservation2DRangeScan& obs,
							  const TScan2D& scan, double turnRate, double appliedTurn,
							  const TPose2D& step, bool matched)
{
	if (m_fixed) return;
	m_pose = m_recent.empty() ? TPose2D(0, 0, 0) : compose(m_pose, step);
	TRecent cur;
	cur.pose = m_pose;
	cur.turnRate = turnRate;
	cur.appliedTurn = appliedTurn;
	cur.matched = matched;
	cur.fractions = sweepFractions(obs);
	const bool usable = matched && cur.fractions.size() == scan.points.size();
	if (usable) cur.scan = scan;
	if (TRecent* ref = usable ? referenceFor(cur) : nullptr)
	{
		if (!ref->cloud)
			ref->cloud = std::make_shared<const CReferenceCloud>(
				CReferenceCloud::fromScan(ref->scan, m_matcher));
		if (auto fit = fitSkew(*ref->cloud, scan, cur.fractions, between(ref->pose, cur.pose)))
			addSample(cur.turnRate - ref->turnRate,
					  fit->skew + cur.appliedTurn - ref->appliedTurn,
					  kStdInflation * fit->skewStd);
	}
	if (!usable) cur.fractions.clear();
	m_recent.push_back(std::move(cur));
	if (m_recent.size() > kRecentScans) m_recent.pop_front();
}

// The recent matched scan whose turn rate differs most from cur's, by at least
// min_rate_change_per_s (and at most kMaxRateChange), taken close enough to overlap.
CSweepEstimator::TRecent* CSweepEstimator::referenceFor(const TRecent& cur)
{
	TRecent* best = nullptr;
	double bestChange = m_params.min_rate_change_per_s;
	for (TRecent& r : m_recent)
	{
		if (!r.matched || r.fractions.empty()) continue;
		const TPose2D d = between(r.pose, cur.pose);
		if (translationNorm(d) > kMaxPairDistance || std::abs(d.phi) > kMaxPairTurn) continue;
		const double change = std::abs(cur.turnRate - r.turnRate);
		if (change >= bestChange && change <= kMaxRateChange) best = &r, bestChange = change;
	}
	return best;
}

void CSweepEstimator::addSample(double x, double y, double std)
{
	if (m_fixed || !(std > 0) || !std::isfinite(x) || !std::isfinite(y)) return;
	const double h = m_params.max_sweep_time_s / double(kGridSteps);
	for (size_t g = 0; g <= kGridSteps; ++g)
	{
		const double u = (y - double(g) * h * x) / (kCauchy * std);
		m_loss[g] += std::log1p(u * u);
	}
	if (m_samples.size() < kMaxSamples)
		m_samples.push_back({x, y, std});
	else
		m_samples[m_nextSample++ % kMaxSamples] = {x, y, std};
	++m_summary.samples;
	updateEstimate();
}

// The grid minimum, refined by a parabola through it and its neighbours; its standard error
// by the sandwich formula of an M-estimator, rho(r) = c^2/2 log(1 + r^2/c^2),
// r_i = (y_i - tau x_i) / std_i, z_i = x_i / std_i:
//     var(tau) = sum psi(r_i)^2 z_i^2 / (sum psi'(r_i) z_i^2)^2.
void CSweepEstimator::updateEstimate()
{
	const double h = m_params.max_sweep_time_s / double(kGridSteps);
	const size_t g = size_t(std::min_element(m_loss.begin(), m_loss.end()) - m_loss.begin());
	double tau = double(g) * h;
	if (g > 0 && g < kGridSteps)
	{
		const double l0 = m_loss[g - 1], l1 = m_loss[g], l2 = m_loss[g + 1];
		const double den = l0 - 2 * l1 + l2;
		if (den > 0) tau += 0.5 * h * (l0 - l2) / den;
	}
	m_summary.estimate = tau;
	if (m_summary.samples < m_params.min_samples) return;
	double meat = 0, bread = 0;
	const double c2 = kCauchy * kCauchy;
	for (const TSample& s : m_samples)
	{
		const double r = (s.y - tau * s.x) / s.std, z = s.x / s.std, q = r * r / c2;
		const double psi = r / (1 + q), dpsi = (1 - q) / ((1 + q) * (1 + q));
		meat += psi * psi * z * z;
		bread += dpsi * z * z;
	}
	if (bread <= 0) return;
	m_summary.std = std::sqrt(meat) / bread;
	if (m_summary.std <= m_params.max_std_s) m_summary.estimated = true;
	if (m_summary.estimated) m_summary.sweepTime = tau;
}

}  // namespace lrgc
