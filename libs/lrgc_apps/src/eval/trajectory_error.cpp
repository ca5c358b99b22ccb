/* Absolute trajectory error after best-fit SE(2) alignment, and ground-truth relations for
 * the relative trajectory error. Formulas in trajectory_error.h. */
#include "lrgc_apps/eval/trajectory_error.h"

#include <lrgc/common/se2.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/math/wrap2pi.h>

#include <algorithm>
#include <cmath>

namespace lrgc::apps::eval
{
using mrpt::math::TPose2D;

TPose2D bestFitRigid2D(const std::vector<TPose2D>& from, const std::vector<TPose2D>& to)
{
	ASSERT_EQUAL_(from.size(), to.size());
	ASSERTMSG_(!from.empty(), "bestFitRigid2D: no point pairs");
	const double n = static_cast<double>(from.size());
	double pcx = 0, pcy = 0, gcx = 0, gcy = 0;
	for (std::size_t i = 0; i < from.size(); ++i)
		pcx += from[i].x, pcy += from[i].y, gcx += to[i].x, gcy += to[i].y;
	pcx /= n, pcy /= n, gcx /= n, gcy /= n;
	double sumCos = 0, sumSin = 0;  // sum g'.p'  and  sum g' x p'  (z of the cross product)
	for (std::size_t i = 0; i < from.size(); ++i)
	{
		const double px = from[i].x - pcx, py = from[i].y - pcy;
		const double gx = to[i].x - gcx, gy = to[i].y - gcy;
		sumCos += gx * px + gy * py;
		sumSin += gy * px - gx * py;
	}
	const double theta = (sumCos == 0 && sumSin == 0) ? 0.0 : std::atan2(sumSin, sumCos);
	const double c = std::cos(theta), s = std::sin(theta);
	return {gcx - (c * pcx - s * pcy), gcy - (s * pcx + c * pcy), theta};
}

TAbsoluteTrajectoryError evaluateAte(const CTrajectory2D& estimate,
									 const CTrajectory2D& groundTruth, double exactTolerance_s)
{
	TAbsoluteTrajectoryError ate;
	std::vector<TPose2D> est, gt;
	for (std::size_t i = 0; i < groundTruth.size(); ++i)
	{
		const TTimedPose2D& g = groundTruth.poses()[i];
		const auto p = estimate.poseAt(g.t, exactTolerance_s);
		if (!p)
		{
			ate.unmatchedGroundTruth.push_back(i);
			continue;
		}
		est.push_back(p->pose);
		gt.push_back(g.pose);
	}
	if (est.empty())
		THROW_EXCEPTION_FMT(
			"ATE: none of the %zu ground-truth timestamps lies within the estimated "
			"trajectory's time span",
			groundTruth.size());
	ate.matched = est.size();
	ate.alignment = bestFitRigid2D(est, gt);
	std::vector<double> trans, rot;
	for (std::size_t i = 0; i < est.size(); ++i)
	{
		const TPose2D aligned = lrgc::compose(ate.alignment, est[i]);
		trans.push_back(std::hypot(aligned.x - gt[i].x, aligned.y - gt[i].y));
		rot.push_back(std::abs(mrpt::math::wrapToPi(aligned.phi - gt[i].phi)) * 180.0 / M_PI);
	}
	ate.trans_m = TErrorStats::fromSamples(trans);
	ate.rot_deg = TErrorStats::fromSamples(rot);
	return ate;
}

namespace
{
TRelation relationBetween(const TTimedPose2D& a, const TTimedPose2D& b)
{
	TRelation r;
	r.t1 = a.t;
	r.t2 = b.t;
	r.motion = lrgc::between(a.pose, b.pose);
	r.line = a.line;
	return r;
}
}  // namespace

std::vector<TRelation> relationsOverSteps(const CTrajectory2D& groundTruth, std::size_t step)
{
	ASSERTMSG_(step >= 1, "relationsOverSteps: step must be >= 1");
	std::vector<TRelation> out;
	const auto& g = groundTruth.poses();
	for (std::size_t i = 0; i + step < g.size(); ++i)
		out.push_back(relationBetween(g[i], g[i + step]));
	return out;
}

std::vector<TRelation> relationsOverDistance(const CTrajectory2D& groundTruth,
											 double distance_m)
{
	ASSERTMSG_(distance_m > 0, "relationsOverDistance: distance must be > 0");
	const auto& g = groundTruth.poses();
	// cumulative[i]: path length from pose 0 to pose i [m]
	std::vector<double> cumulative(g.size(), 0.0);
	for (std::size_t i = 1; i < g.size(); ++i)
		cumulative[i] = cumulative[i - 1] + std::hypot(g[i].pose.x - g[i - 1].pose.x,
													   g[i].pose.y - g[i - 1].pose.y);
	std::vector<TRelation> out;
	std::size_t j = 0;
	for (std::size_t i = 0; i < g.size(); ++i)
	{
		j = std::max(j, i + 1);
		while (j < g.size() && cumulative[j] - cumulative[i] < distance_m) ++j;
		if (j >= g.size()) break;
		out.push_back(relationBetween(g[i], g[j]));
	}
	return out;
}

}  // namespace lrgc::apps::eval
