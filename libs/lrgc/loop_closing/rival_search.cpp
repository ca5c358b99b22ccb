/* Step 4 of a correlation query: the rival search and the ridge rules; see rival_search.h. */
#include "rival_search.h"

#include <mrpt/math/wrap2pi.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace lrgc::detail
{
namespace
{
/** Step 4: rivals found on the best peak's ridge, whose clusters join the best's, at most. */
constexpr int kMaxRidgeDiscs = 8;

/** True if every pose on the straight path from `from` to `to` in the pose grid (headings and
 * cells interpolated, one sample per cell or heading step) scores at least `floor`: `to` lies
 * on a ridge of `from`'s peak, not on a peak of its own (no valley between them). */
bool joinedAbove(const TPoseGridProblem& pb, const TSearchHit& from, const TSearchHit& to,
				 int64_t floor)
{
	const int steps = std::max(
		{std::abs(to.a - from.a), std::abs(to.i - from.i), std::abs(to.j - from.j), 1});
	for (int k = 1; k < steps; ++k)
	{
		const double t = double(k) / steps;
		const auto at = [t](int x0, int x1) { return int(std::lround(x0 + t * (x1 - x0))); };
		if (scoreAt(pb, 0, at(from.a, to.a), at(from.i, to.i), at(from.j, to.j)) < floor)
			return false;
	}
	return true;
}

/** Whether `rival` may join the straight ridge `ridge` of `best` (see TRidgeRule::Straight);
 * extends the ridge if so. */
bool joinStraightRidge(const TPatchCorrelatorParams& prm, const TGridSpec& spec, int halfCells,
					   const TSearchHit& best, const TSearchHit& rival, TRidge& ridge)
{
	// A rival within a cluster radius of the window's border may have the ridge go on outside
	// it (the true place beyond the window): the ridge's extent is not known, it stays a rival.
	const int border = halfCells - int(std::ceil(prm.cluster_radius_m / spec.res));
	if (std::max(std::abs(rival.i), std::abs(rival.j)) > border ||
		std::max(std::abs(best.i), std::abs(best.j)) > border)
		return false;
	const double dTheta = mrpt::math::wrapToPi(spec.theta(rival.a) - spec.theta(best.a));
	const Eigen::Vector2d d(double(rival.i - best.i) * spec.res,
							double(rival.j - best.j) * spec.res);
	if (std::abs(dTheta) > prm.max_std_phi || d.norm() < spec.res) return false;
	if (ridge.axis.isZero()) ridge.axis = d.normalized();
	const double across = std::abs(ridge.axis.x() * d.y() - ridge.axis.y() * d.x());
	if (across > prm.cluster_radius_m) return false;
	ridge.halfLength =
		std::max(ridge.halfLength, std::abs(ridge.axis.dot(d)) + prm.cluster_radius_m);
	ridge.maxDeltaTheta = std::max(ridge.maxDeltaTheta, std::abs(dTheta));
	return true;
}

/** Whether the straight ridge `ridge` of `best` reaches the window's centre (the gate's
 * prediction, cell (0, 0)) along its axis a, within a cluster radius r of its end (L its
 * half-length, b the best pose's cell offset; grid frame, m):
 *     |a . (0 - b res)| <= L + r.
 * Only then is the prediction the guess along the ridge that the loop link is seeded at
 * (CLoopCloser::seedOnRidge, which clamps it to +-L); a prediction beyond the ridge's end
 * says the look-alikes lie elsewhere along the corridor than the robot, and the true place
 * may be a stretch the patch matches less well (the first 300 scans of
 * SparseScans.TurnsOfEightyDegrees: a ridge of +-3.7 m 8.9 m from the prediction, its link,
 * seeded at the ridge's end, 5.6 m along the corridor from the truth, chi2 19.2 with the
 * ridge's doubt). */
bool ridgeReachesCentre(const TPatchCorrelatorParams& prm, const TGridSpec& spec,
						const TSearchHit& best, const TRidge& ridge)
{
	const Eigen::Vector2d toCentre(-double(best.i) * spec.res, -double(best.j) * spec.res);
	return std::abs(ridge.axis.dot(toCentre)) <= ridge.halfLength + prm.cluster_radius_m;
}
}  // namespace

/** Step 4's exclusion zone: the best pose's cluster, the headings within cluster_radius_phi_deg
 * and the cells within cluster_radius_m of it [cells^2]. */
TExclusionDisc bestCluster(const TPatchCorrelatorParams& prm, const TGridSpec& spec,
						   int numAngles, const TSearchHit& best)
{
	TExclusionDisc zone;
	zone.inAngle.resize(size_t(numAngles));
	for (int a = 0; a < numAngles; ++a)
		zone.inAngle[size_t(a)] =
			std::abs(mrpt::math::wrapToPi(spec.theta(a) - spec.theta(best.a))) <=
			prm.cluster_radius_phi + 1e-12;
	zone.ci = best.i, zone.cj = best.j;
	zone.r2 = std::pow(prm.cluster_radius_m / spec.res, 2) + 1e-9;
	return zone;
}

TSearchHit searchRival(const TRivalSearch& search, const TPatchCorrelatorParams& prm,
					   TRidgeRule rule, const TPoseGridProblem& pb, const TGridSpec& spec,
					   const TSearchHit& best, int64_t floor, TRidge& ridge)
{
	TExclusionZone cluster;
	cluster.discs.push_back(bestCluster(prm, spec, pb.numAngles, best));
	TSearchHit rival = search(floor, cluster, true);
	const auto joinFloor =
		static_cast<int64_t>(std::ceil(double(best.score) / prm.min_ambiguity - 1e-9));
	const auto joins = [&](const TSearchHit& r)
	{
		if (rule == TRidgeRule::None) return false;
		if (rule == TRidgeRule::AnyJoined) return joinedAbove(pb, best, r, joinFloor);
		if (r.score < joinFloor) return false;  // it cannot fail filter 2 (exhaustive search)
		TRidge grown = ridge;
		if (!joinStraightRidge(prm, spec, pb.halfCells, best, r, grown)) return false;
		// The first rival joined sets the ridge's axis and first step: the window's centre
		// beyond its reach, the look-alikes lie away from where the robot is predicted, and
		// the rival stays the rival (filter 2), at the paper's cost.
		if (ridge.axis.isZero() && !ridgeReachesCentre(prm, spec, best, grown)) return false;
		ridge = grown;
		return true;
	};
	size_t ridgeEvaluations = 0;
	for (int grown = 0; rival.found && !rival.stopped && grown < kMaxRidgeDiscs && joins(rival);
		 ++grown)
	{
		ridgeEvaluations += rival.evaluations;
		cluster.discs.push_back(bestCluster(prm, spec, pb.numAngles, rival));
		rival = search(floor, cluster, true);
	}
	rival.evaluations += ridgeEvaluations;
	return rival;
}

}  // namespace lrgc::detail
