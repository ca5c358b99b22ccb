#include <lrgc/map_builder/ScanSmoothing.h>

#include <lrgc/common/OrderStatistic.h>
#include <lrgc/common/se2.h>
#include <lrgc/pose_graph/PoseGraphOptimizer.h>

#include <Eigen/LU>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>

namespace lrgc
{
using mrpt::math::TPose2D;

namespace
{
constexpr double kGateChi2 = 11.34;  //!< chi2 with 3 dof, 99 %: Huber's threshold g
constexpr int kIterations = 3;       //!< Gauss-Newton steps (the start is close: 1-2 suffice)
constexpr double kChi2Median1 = 0.4549;      //!< median of chi2 with 1 dof
constexpr size_t kMinCalibrationSteps = 20;  //!< fewer steps: the model's covariance as is
/** Lower bound of s_c^2: a hundredth of the modelled std, so that an odometry that agrees
 * perfectly with the registration does not take all the weight. */
constexpr double kMinNoiseScale = 1e-4;
/** Added to each P_k [m^2, m^2, rad^2] so that a zero covariance stays invertible. */
const Eigen::Vector3d kPriorFloor(1e-8, 1e-8, 1e-10);

/** One run a+1..b-1 of scans that are not keyframes; a, b fixed (none past either end). */
struct TRun
{
	size_t first, last;  //!< the free scans, inclusive
	size_t n() const { return last - first + 1; }
};

/** The odometry steps of the run's problem: k with k-1 and k in [first-1, last+1] and in
 * range, odometry into k, and its Huber weight at the registered poses. */
struct TStepFactor
{
	size_t k;
	Eigen::Matrix3d info;  //!< w_k (s^2 Q_k)^-1
};

/** The run's pose of scan k: x[k - first] if k is free, its fixed pose otherwise. */
TPose2D poseOf(const std::vector<TScanStep>& s, const TRun& r, const std::vector<TPose2D>& x,
			   size_t k)
{
	return k >= r.first && k <= r.last ? x[k - r.first] : s[k].pose;
}

std::vector<TStepFactor> stepFactors(const std::vector<TScanStep>& s, const TRun& r,
									 const Eigen::Vector3d& scale,
									 const std::vector<TPose2D>& x)
{
	std::vector<TStepFactor> f;
	const size_t from = std::max<size_t>(r.first, 1), to = std::min(r.last + 1, s.size() - 1);
	for (size_t k = from; k <= to; ++k)
	{
		if (!s[k].fromOdometry) continue;
		const Eigen::Matrix3d info =
			(scale.asDiagonal() * s[k].stepCov * scale.asDiagonal()).inverse();
		const Eigen::Vector3d e =
			linkResidual(poseOf(s, r, x, k - 1), poseOf(s, r, x, k), s[k].odometryStep);
		const double chi2 = e.dot(info * e);
		f.push_back({k, info * std::min(1.0, kGateChi2 / std::max(chi2, 1e-12))});
	}
	return f;
}

/** Adds the 3x3 block B at block (i, j) of the triplet list. */
void addBlock(std::vector<Eigen::Triplet<double>>& t, size_t i, size_t j,
			  const Eigen::Matrix3d& B)
{
	for (int r = 0; r < 3; ++r)
		for (int c = 0; c < 3; ++c) t.emplace_back(int(3 * i) + r, int(3 * j) + c, B(r, c));
}

/** One Gauss-Newton step on the run's poses x (x[j]: scan first + j); false if singular. */
bool gaussNewtonStep(const std::vector<TScanStep>& s, const TRun& r,
					 const std::vector<TStepFactor>& steps, std::vector<TPose2D>& x)
{
	const size_t n = r.n();
	std::vector<Eigen::Triplet<double>> t;
	Eigen::VectorXd g = Eigen::VectorXd::Zero(3 * long(n));
	for (size_t j = 0; j < n; ++j)
	{  // registration: r = x_k - p_k (phi wrapped), information P_k^-1
		const TScanStep& sk = s[r.first + j];
		const Eigen::Matrix3d info =
			(sk.poseCov + Eigen::Matrix3d(kPriorFloor.asDiagonal())).inverse();
		Eigen::Vector3d e = toVector(x[j]) - toVector(sk.pose);
		e.z() = mrpt::math::wrapToPi(e.z());
		addBlock(t, j, j, info);
		g.segment<3>(3 * long(j)) += info * e;
	}
	auto poseOf = [&](size_t k) { return lrgc::poseOf(s, r, x, k); };
	auto isFree = [&](size_t k) { return k >= r.first && k <= r.last; };
	for (const TStepFactor& f : steps)
	{
		Eigen::Matrix3d J1, J2;
		const Eigen::Vector3d e =
			linkResidual(poseOf(f.k - 1), poseOf(f.k), s[f.k].odometryStep, &J1, &J2);
		const size_t i1 = f.k - 1 - r.first, i2 = f.k - r.first;  // valid where free
		if (isFree(f.k - 1))
			addBlock(t, i1, i1, J1.transpose() * f.info * J1),
				g.segment<3>(3 * long(i1)) += J1.transpose() * f.info * e;
		if (isFree(f.k))
			addBlock(t, i2, i2, J2.transpose() * f.info * J2),
				g.segment<3>(3 * long(i2)) += J2.transpose() * f.info * e;
		if (isFree(f.k - 1) && isFree(f.k))
			addBlock(t, i1, i2, J1.transpose() * f.info * J2),
				addBlock(t, i2, i1, J2.transpose() * f.info * J1);
	}
	Eigen::SparseMatrix<double> H(3 * long(n), 3 * long(n));
	H.setFromTriplets(t.begin(), t.end());
	const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(H);
	if (ldlt.info() != Eigen::Success) return false;
	const Eigen::VectorXd d = ldlt.solve(-g);
	for (size_t j = 0; j < n; ++j)
		x[j] = fromVector(toVector(x[j]) + d.segment<3>(3 * long(j)));
	return true;
}
}  // namespace

Eigen::Vector3d odometryNoiseScale(const std::vector<TScanStep>& s)
{
	std::vector<double> z2[3];  // e_{i,c}^2 / Q_{i,cc} per component
	for (size_t i = 1; i < s.size(); ++i)
	{
		if (!s[i].fromOdometry) continue;
		// Wheels that did not turn calibrate nothing: a still robot's registration repeats
		// the zero step to the matcher's repeatability, or exactly where its last match is
		// reused (reuse_match_when_still), and ACES stands still for 35 % of its steps: the
		// median would read the matcher, not the odometry (the spread of issue 29's ACES
		// pieces test over six starts, 0.03742 -> 0.03719 m; doc/architecture.md, stop 62).
		if (isZeroStep(s[i].odometryStep)) continue;
		const Eigen::Vector3d e =
			toVector(between(s[i].odometryStep, between(s[i - 1].pose, s[i].pose)));
		for (int c = 0; c < 3; ++c) z2[c].push_back(e[c] * e[c] / s[i].stepCov(c, c));
	}
	if (z2[0].size() < kMinCalibrationSteps) return Eigen::Vector3d::Ones();
	Eigen::Vector3d scale;
	for (int c = 0; c < 3; ++c)
	{
		scale[c] = std::sqrt(std::max(kMinNoiseScale, upperMedian(z2[c]) / kChi2Median1));
	}
	return scale;
}

std::vector<std::pair<size_t, TPose2D>> smoothScans(const std::vector<TScanStep>& s,
													const Eigen::Vector3d& scale)
{
	std::vector<std::pair<size_t, TPose2D>> smoothed;
	for (size_t first = 0; first < s.size();)
	{
		if (s[first].keyframe)
		{
			++first;
			continue;
		}
		size_t last = first;
		while (last + 1 < s.size() && !s[last + 1].keyframe) ++last;
		const TRun run{first, last};
		std::vector<TPose2D> x;
		for (size_t k = first; k <= last; ++k) x.push_back(s[k].pose);
		bool ok = true;
		for (int it = 0; it < kIterations && ok; ++it)
			ok = gaussNewtonStep(s, run, stepFactors(s, run, scale, x), x);
		if (ok)  // positions only: the registered heading stays (see the file comment)
			for (size_t k = first; k <= last; ++k)
				smoothed.emplace_back(k,
									  TPose2D(x[k - first].x, x[k - first].y, s[k].pose.phi));
		first = last + 1;
	}
	return smoothed;
}

}  // namespace lrgc
