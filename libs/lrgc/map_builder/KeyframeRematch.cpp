#include <lrgc/map_builder/KeyframeRematch.h>

#include <lrgc/common/HelperThread.h>
#include <lrgc/common/SharedLoop.h>
#include <lrgc/common/se2.h>
#include <lrgc/scan_matching/ReferenceCloud.h>

#include <Eigen/Dense>
#include <algorithm>
#include <functional>
#include <limits>
#include <optional>

namespace lrgc
{
using mrpt::math::TPose2D;

namespace
{
/** [m] The reference's keyframes lie within this of k's position: the robot's own path
 * around k (a sparse log's scans 1 m apart: the three before and after) and the revisits
 * there, as the end-of-run revisit sweep's region (3 radius_m, RevisitLinker.h). The
 * position of an unmatched keyframe is its odometry step's, off by decimetres, well inside. */
constexpr double kNeighbourRadius = 3.0;

/** Keyframes whose indices differ by at most this are one visit of the place (the robot's
 * path through it, placed by local registration alone): a sparse log's keyframes within
 * kNeighbourRadius are 1 m apart (indices +- 3), the atrium's 0.4 m (+- 7); a gap of more
 * than kVisitGap keyframes is the robot leaving and coming back. */
constexpr size_t kVisitGap = 3;

/** Nodes within kNeighbourRadius of k, on k's side of `split`, nearest first. */
std::vector<size_t> neighboursOf(const CPoseGraph& g, size_t k, size_t split)
{
	std::vector<std::pair<double, size_t>> near;
	const TPose2D pk = g.pose(k);
	for (size_t j = 0; j < g.numNodes(); ++j)
	{
		if (j == k || (j < split) != (k < split)) continue;
		const double d = translationNorm(between(g.pose(j), pk));
		if (d < kNeighbourRadius) near.emplace_back(d, j);
	}
	std::sort(near.begin(), near.end());
	std::vector<size_t> out;
	for (const auto& [d, j] : near) out.push_back(j);
	return out;
}
/** The scans of keyframes `nodes` as one reference cloud, in node r's frame (r <- j). */
CReferenceCloud cloudOf(const CPoseGraph& g, const TKeyframes& keyframes,
						const std::vector<size_t>& nodes, size_t r, const TScanMatcherParams& p,
						const TParallelFor& parallel)
{
	std::vector<TScan2D> scans;
	std::vector<TPose2D> inR;
	for (const size_t j : nodes)
	{
		scans.push_back(keyframes[j].scan);
		inR.push_back(between(g.pose(r), g.pose(j)));
	}
	return CReferenceCloud::fromScans(scans, inR, p, parallel);
}
}  // namespace

CKeyframeRematcher::CKeyframeRematcher(const TScanMatcherParams& matcher, double wideAngle,
									   double gateChi2, const Eigen::Matrix3d& weakOdometryCov,
									   const TLinkNoise& linkNoise)
	: m_params(matcher),
	  m_matcher(matcher),
	  m_wideAngle(wideAngle),
	  m_gateChi2(gateChi2),
	  m_weakOdometryCov(weakOdometryCov),
	  m_linkNoise(linkNoise)
{
}

std::vector<TRematchedKeyframe> CKeyframeRematcher::rematch(
	CPoseGraph& graph, const TKeyframes& keyframes, const std::vector<size_t>& candidates,
	size_t split) const
{
	std::vector<TRematchedKeyframe> moved;
	if (m_wideAngle <= 0) return moved;
	// A second thread shares the reference's line fits and the wide search's starts
	// (CSharedLoop: the same result on any number of threads).
	CHelperThread helper;
	const TParallelFor parallel = [&helper](size_t count, const std::function<void(size_t)>& fn)
	{ runShared(helper, count, fn); };
	for (const size_t k : candidates)
	{
		if (m_stop.stopRequested()) break;
		const std::vector<size_t> near = neighboursOf(graph, k, split);
		if (near.empty()) continue;
		const size_t r = near.front();
		const CReferenceCloud ref = cloudOf(graph, keyframes, near, r, m_params, parallel);
		const TPose2D guess = between(graph.pose(r), graph.pose(k));
		const auto m =
			m_matcher.matchWide(ref, keyframes[k].scan, guess, m_wideAngle, parallel);
		if (!m || !CScanMatcher::distinctHypotheses(guess, m->scanInRef) ||
			!visitsAgree(graph, keyframes, k, r, near, *m, parallel))
			continue;
		moved.push_back({k, graph.pose(k)});
		relink(graph, keyframes, k, r, *m);
	}
	return moved;
}

/* Step 2's second opinion: the reference mixes every visit of the place, each placed by the
 * map; where the map has two visits apart (laps not yet aligned there), the wide match wins on
 * the visit that explains most of the scan, but the link is read in r's frame. So k's scan,
 * matched from the winner against each visit alone (in r's frame), must stay there: a visit
 * whose own match converges elsewhere (chi2 of the two poses under both covariances and twice
 * the loop links' noise floor above m_gateChi2, or distinct hypotheses) says the map is no
 * evidence at this place, and k stays where it is. A visit that does not match k's scan at
 * all (too little of it in view) has no say. */
bool CKeyframeRematcher::visitsAgree(const CPoseGraph& graph, const TKeyframes& keyframes,
									 size_t k, size_t r, const std::vector<size_t>& near,
									 const TScanMatch& m, const TParallelFor& parallel) const
{
	const auto visits = visitsOf(near, kVisitGap);
	if (visits.size() < 2) return true;
	for (const auto& visit : visits)
	{
		const CReferenceCloud ref = cloudOf(graph, keyframes, visit, r, m_params, parallel);
		const auto v = m_matcher.match(ref, keyframes[k].scan, m.scanInRef);
		if (!v) continue;
		const Eigen::Matrix3d C = m.cov + v->cov + 2 * m_linkNoise.floorCovariance();
		if (CScanMatcher::distinctHypotheses(m.scanInRef, v->scanInRef) ||
			disagreementChi2(m.scanInRef, v->scanInRef, C) > m_gateChi2)
			return false;
	}
	return true;
}

void CKeyframeRematcher::relink(CPoseGraph& graph, const TKeyframes& keyframes, size_t k,
								size_t r, const TScanMatch& m) const
{
	graph.setPose(k, compose(graph.pose(r), m.scanInRef));
	graph.addLink({r, k, m.scanInRef,
				   linkInformation(m.cov, denoisedLoopLinkNoise(
											  m_linkNoise, keyframes[k].scan.rangeNoiseStd)),
				   LinkType::LoopClosure});
	// The links of k the new pose contradicts (chi2 under the link's covariance > the gate, or
	// a distinct hypothesis): the odometry that failed, and the window's links made in k's
	// frame while k was off (its patch link to the next keyframe measures that keyframe
	// against the window's map expressed at k's wrong pose). Each is disabled and replaced by
	// the relative pose as it now stands at the constant-velocity noise, same type (as local
	// registration's odometry link after a wide-search override,
	// CMetricMapBuilderLRGC::odometryLink): the graph stays joined, nothing pulls k back.
	const std::vector<size_t> ids = graph.linksOf(k);  // a copy: links are added below
	for (const size_t id : ids)
	{
		const TLink l = graph.link(id);
		if (l.type == LinkType::LoopClosure || !graph.isLinkEnabled(id)) continue;
		const TPose2D now = between(graph.pose(l.from), graph.pose(l.to));
		if (disagreementChi2(l.toInFrom, now, l.information.inverse()) <= m_gateChi2 &&
			!CScanMatcher::distinctHypotheses(l.toInFrom, now))
			continue;
		graph.setLinkEnabled(id, false);
		graph.addLink({l.from, l.to, now, m_weakOdometryCov.inverse(), l.type});
	}
}

}  // namespace lrgc
