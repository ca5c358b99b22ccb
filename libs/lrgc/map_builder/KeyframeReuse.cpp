#include <lrgc/map_builder/KeyframeReuse.h>

#include <lrgc/common/se2.h>
#include <lrgc/scan_matching/ReferenceCloud.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace lrgc
{
using mrpt::math::TPose2D;

CKeyframeReuse::CKeyframeReuse(const TKeyframeReuseParams& p, double keyframeDistance,
							   double keyframeAngle, const TScanMatcherParams& matcher,
							   const TLinkNoise& floor)
	: m_params(p),
	  m_distance(keyframeDistance),
	  m_angle(keyframeAngle),
	  m_matcher(matcher),
	  m_floor(floor)
{
}

void CKeyframeReuse::noteLoopLink(size_t node)
{
	m_lastLinked = std::max(node, m_lastLinked.value_or(0));
}

std::optional<TReusedKeyframe> CKeyframeReuse::reusableKeyframe(
	const CPoseGraph& graph, const TKeyframes& keyframes, const TScan2D& scan,
	const TPose2D& scanInMap, const CLazyCovariance& scanCov, size_t anchor,
	const std::deque<size_t>& window) const
{
	const size_t newest = graph.numNodes() - 1;
	if (!m_params.enabled || !m_lastLinked || newest > *m_lastLinked + m_params.trust_keyframes)
		return std::nullopt;
	// The nearest covering keyframe, in units of the keyframe spacing:
	// max(d / keyframe_distance_m, |dphi| / keyframe_angle) < 1.
	std::optional<size_t> best;
	double bestNorm = 1.0;
	for (size_t c = m_firstCandidate; c <= newest; ++c)
	{
		if (c == anchor) continue;  // (also in the window: skipped below)
		const TPose2D& p = graph.pose(c);
		const double dx = scanInMap.x - p.x, dy = scanInMap.y - p.y;
		if (std::abs(dx) >= m_distance || std::abs(dy) >= m_distance) continue;
		const double norm =
			std::max(std::hypot(dx, dy) / m_distance,
					 std::abs(mrpt::math::wrapToPi(scanInMap.phi - p.phi)) / m_angle);
		if (norm >= bestNorm) continue;
		if (std::find(window.begin(), window.end(), c) != window.end()) continue;
		best = c, bestNorm = norm;
	}
	if (!best) return std::nullopt;

	// The scan where its registration puts it, matched against c's own scan.
	const TPose2D cInMap = graph.pose(*best);
	const TPose2D guess = between(cInMap, scanInMap);
	const auto m = m_matcher.match(
		CReferenceCloud::fromScan(keyframes[*best].scan, m_matcher.params()), scan, guess);
	// A match the scans leave free along some direction (a bare corridor) cannot tell the
	// estimate and the map apart there: no reuse, a new keyframe and a loop search instead.
	if (!m || m->unobservableDims > 0 || m->inlierFraction < m_params.min_inlier_fraction)
		return std::nullopt;
	// scanCov in c's axes, plus the match's, plus the floor of scans taken at other times.
	const Eigen::Matrix3d C =
		rotateCovariance(scanCov.get(), -cInMap.phi) + m->cov + m_floor.floorCovariance();
	if (disagreementChi2(guess, m->scanInRef, C) > m_params.gate_chi2) return std::nullopt;
	return TReusedKeyframe{*best, m->scanInRef, m->cov};
}

}  // namespace lrgc
