#include <lrgc/loop_closing/RevisitLinker.h>

#include <lrgc/scan_matching/ReferenceCloud.h>
#include <lrgc/common/HelperThread.h>
#include <lrgc/common/SharedLoop.h>
#include <lrgc/common/params_io.h>
#include <lrgc/common/se2.h>

#include <mrpt/config/CConfigFileBase.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <unordered_map>
#include <unordered_set>

namespace lrgc
{
using mrpt::math::TPose2D;

CRevisitLinker::CRevisitLinker(const TRevisitLinkerParams& p, const TScanMatcherParams& matcher,
							   const TLinkNoise& linkNoise)
	: m_params(p),
	  m_matcherParams(matcher),
	  m_linkNoise(linkNoise),
	  m_matcher(matcher),
	  m_patchMatcher(
		  [&matcher]
		  {
			  TScanMatcherParams q = matcher;
			  q.max_free_space_violation = 1.0;
			  return q;
		  }())
{
}

namespace
{
uint64_t pairKey(size_t a, size_t b)
{
	if (a > b) std::swap(a, b);
	return (uint64_t(a) << 32) | uint64_t(b);
}
uint64_t cellKey(int64_t ix, int64_t iy)
{
	return (uint64_t(uint32_t(ix)) << 32) | uint32_t(iy);
}
}  // namespace

/* The sweep's state: existing links, a hash grid (cells of side radius_m) over the keyframe
 * positions, and the path [m] from node 0 to each node. */
struct CRevisitLinker::TSweep
{
	const CPoseGraph& graph;
	std::unordered_set<uint64_t> linked;
	std::unordered_map<uint64_t, std::vector<size_t>> cells;
	std::vector<double> path;

	TSweep(const CPoseGraph& g, double r) : graph(g), path(g.numNodes(), 0.0)
	{
		for (size_t id = 0; id < g.numLinks(); ++id)
			if (g.isLinkEnabled(id)) linked.insert(pairKey(g.link(id).from, g.link(id).to));
		for (size_t j = 0; j < g.numNodes(); ++j)
		{
			const TPose2D p = g.pose(j);
			cells[cellKey(int64_t(std::floor(p.x / r)), int64_t(std::floor(p.y / r)))]
				.push_back(j);
			if (j > 0) path[j] = path[j - 1] + translationNorm(between(g.pose(j - 1), p));
		}
	}
	/** A link between k +- 2 and j +- 2 already? */
	bool linkedNear(size_t k, size_t j) const
	{
		const size_t n = graph.numNodes();
		for (size_t a = k > 2 ? k - 2 : 0; a <= std::min(n - 1, k + 2); ++a)
			for (size_t b = j > 2 ? j - 2 : 0; b <= std::min(n - 1, j + 2); ++b)
				if (linked.count(pairKey(a, b))) return true;
		return false;
	}
};

/** Old keyframes j of k (index and path gap, same frame) within `reach` [m] of k's position,
 * with their distance; the grid's cells within reach. */
std::vector<std::pair<size_t, double>> CRevisitLinker::oldNear(const TSweep& sw, size_t k,
															   double reach) const
{
	const TPose2D pk = sw.graph.pose(k);
	const double r = m_params.radius_m;
	const int64_t cx = int64_t(std::floor(pk.x / r)), cy = int64_t(std::floor(pk.y / r));
	const int64_t span = int64_t(std::ceil(reach / r));
	std::vector<std::pair<size_t, double>> out;
	for (int64_t dx = -span; dx <= span; ++dx)
		for (int64_t dy = -span; dy <= span; ++dy)
		{
			const auto it = sw.cells.find(cellKey(cx + dx, cy + dy));
			if (it == sw.cells.end()) continue;
			for (const size_t j : it->second)
			{
				if (j + m_params.min_index_gap >= k || (j < m_split) != (k < m_split) ||
					sw.path[k] - sw.path[j] < m_params.min_path_gap_m)
					continue;
				const double d = translationNorm(between(sw.graph.pose(j), pk));
				if (d < reach) out.emplace_back(j, d);
			}
		}
	return out;
}

/* The old keyframes within 3 radius_m of k, as placed by the map in old's frame, cropped to
 * where `points` (k's frame) fall at `at` (old <- k), as the loop closer's step 3: the margin
 * covers the match's reach plus the widest line fit. */
CReferenceCloud CRevisitLinker::oldRegion(const TSweep& sw, const TKeyframes& keyframes,
										  size_t k, size_t old,
										  const std::vector<Eigen::Vector2d>& points,
										  const TPose2D& at, const TParallelFor& parallel,
										  bool withViews) const
{
	std::vector<TScan2D> scans;
	std::vector<TPose2D> inOld;
	for (const auto& [j, d] : oldNear(sw, k, 3 * m_params.radius_m))
	{
		scans.push_back(keyframes[j].scan);
		inOld.push_back(between(sw.graph.pose(old), sw.graph.pose(j)));
	}
	std::vector<Eigen::Vector2d> inOldFrame;
	const CPointTransform toOld(at);
	for (const auto& p : points) inOldFrame.push_back(toOld(p));
	const double margin =
		m_matcherParams.max_correspondence_dist_m + 4 * m_matcherParams.normal_radius_m + 0.2;
	return CReferenceCloud::fromScansNear(scans, inOld, m_matcherParams, inOldFrame, margin,
										  parallel, withViews);
}

/* k's candidate, unless k and it are already linked near, and the reference to match it
 * against: the nearest old keyframe within radius_m and max_phi, alone; else (any_heading) the
 * nearest within radius_m at any heading, with every old keyframe within 3 radius_m placed
 * around it, cropped to where k's points fall at the guess (as the loop closer's step 3). */
std::optional<CRevisitLinker::TCandidate> CRevisitLinker::candidate(
	const TSweep& sw, const TKeyframes& keyframes, size_t k, const TParallelFor& parallel) const
{
	const TPose2D pk = sw.graph.pose(k);
	const auto near = oldNear(sw, k, m_params.radius_m);
	std::optional<std::pair<size_t, double>> same, any;
	for (const auto& [j, d] : near)
	{
		if (!any || d < any->second) any = {j, d};
		if (std::abs(mrpt::math::wrapToPi(sw.graph.pose(j).phi - pk.phi)) <= m_params.max_phi &&
			(!same || d < same->second))
			same = {j, d};
	}
	if (!same && (!m_params.any_heading || !any)) return std::nullopt;
	TCandidate c;
	c.old = same ? same->first : any->first;
	if (sw.linkedNear(k, c.old)) return std::nullopt;  // before its reference is built
	c.guess = between(sw.graph.pose(c.old), pk);
	if (same)
	{
		c.single = true;
		c.reference = std::make_shared<const CReferenceCloud>(
			CReferenceCloud::fromScan(keyframes[c.old].scan, m_matcherParams));
		return c;
	}
	c.reference = std::make_shared<const CReferenceCloud>(
		oldRegion(sw, keyframes, k, c.old, keyframes[k].scan.points, c.guess, parallel, true));
	return c;
}

/* The second, independent match (see the header), its input: k's patch, as placed by the
 * map, and the old map's region where it falls at `at` (old <- k). */
CRevisitLinker::TPatch CRevisitLinker::patchOf(const TSweep& sw, const TKeyframes& keyframes,
											   size_t k, size_t old, const TPose2D& at,
											   const TParallelFor& parallel) const
{
	const size_t a = m_params.patch_check_keyframes;
	const TPose2D pk = sw.graph.pose(k);
	TPatch out;
	out.patch = keyframes[k].scan;
	out.patch.points.clear();
	for (size_t q = k > a ? k - a : 0; q <= k + a && q < sw.graph.numNodes(); ++q)
	{
		if ((q < m_split) != (k < m_split)) continue;
		const CPointTransform toK(between(pk, sw.graph.pose(q)));
		for (const auto& p : keyframes[q].scan.points) out.patch.points.push_back(toK(p));
	}
	// The patch matcher's free-space check is off (a patch is not one scan's rays): no views.
	out.region = std::make_shared<const CReferenceCloud>(
		oldRegion(sw, keyframes, k, old, out.patch.points, at, parallel, false));
	return out;
}

/* The patch, started where k's scan matched, must stay there: chi2 <= gate_chi2 under both
 * covariances and twice the link noise floor. (Started at the guess instead, a patch whose
 * guess is 0.8 m off along a corridor stays in the guess's basin and refuses a true match:
 * doc/generalisation.md.) The patch match's covariance (a walk over the whole patch's fit
 * neighbourhoods, 0.1-0.2 G instructions on range_030_bearing_015) is deferred, and computed
 * only where the scan match's covariance and the floor alone do not prove agreement
 * (agreesWhateverTheOtherCovariance): the same verdicts. */
bool CRevisitLinker::patchAgrees(const TPatch& p, const TScanMatch& m) const
{
	const auto mp = m_patchMatcher.matchDeferred(p.region, p.patch, m.scanInRef);
	if (!mp) return false;
	const Eigen::Matrix3d floor2 = 2 * m_linkNoise.floorCovariance();
	if (agreesWhateverTheOtherCovariance(m.scanInRef, mp->scanInRef, m.cov + floor2,
										 m_params.gate_chi2))
		return true;
	const Eigen::Matrix3d C = m.cov + mp->covariance().get() + floor2;
	return disagreementChi2(m.scanInRef, mp->scanInRef, C) <= m_params.gate_chi2;
}

/* Every check after the match (the gate against the guess, the patch's agreement, the rivals'
 * distinctness) is read under the match's own covariance, so a match loose enough passes them
 * all by its looseness alone. Any wall the scan matched fixes its heading once its position is
 * fixed: the heading's std with the translation held, 1 / sqrt(Omega_phiphi) of the match's
 * information, is a fraction of a degree for every true revisit link (Killian's corridors
 * included, whose heading alone is loose, 2-4.5 deg, only through the slide along the
 * corridor it goes with). A match that leaves it above max_heading_std matched a blob, not a
 * wall: harsh Intel b80's 83 -> 227 and 83 -> 229 (half the scan matched against a region seen
 * from behind, 2.3-7.8 deg; kept 6.7 and 13.7 deg off the truth). */
bool CRevisitLinker::fixesItsHeading(const TScanMatch& m) const
{
	if (m_params.max_heading_std <= 0) return true;
	const double s = m_params.max_heading_std;
	return m.cov.inverse()(2, 2) * s * s >= 1;
}

namespace
{
/** The ambiguity check's starts, as offsets from the guess (guess's frame): 1 and 2 prior
 * stds along x and along y, 2 in heading. */
std::vector<TPose2D> restartOffsets(double sxy, double sphi)
{
	return {TPose2D(sxy, 0, 0),      TPose2D(-sxy, 0, 0),     TPose2D(0, sxy, 0),
			TPose2D(0, -sxy, 0),     TPose2D(2 * sxy, 0, 0),  TPose2D(-2 * sxy, 0, 0),
			TPose2D(0, 2 * sxy, 0),  TPose2D(0, -2 * sxy, 0), TPose2D(0, 0, 2 * sphi),
			TPose2D(0, 0, -2 * sphi)};
}
}  // namespace

/* One start of the ambiguity check: the scan matched again from guess (+) offset. A rival
 * converges, agrees with the guess as the match must, lies apart from the match
 * (CScanMatcher::distinctHypotheses, and chi2 > gate_chi2 under both covariances and the
 * link noise floor) and explains at least `explained` of the scan
 * (CScanMatcher::explainedFraction): the place is then ambiguous for this scan. Most starts
 * converge back onto the match: their covariance is deferred and never computed. */
bool CRevisitLinker::rivalFrom(const TScan2D& scan, const TCandidate& c, const TScanMatch& m,
							   const Eigen::Matrix3d& prior, double explained,
							   const TPose2D& offset) const
{
	const auto a = m_matcher.matchDeferred(c.reference, scan, compose(c.guess, offset));
	if (!a || !CScanMatcher::distinctHypotheses(m.scanInRef, a->scanInRef)) return false;
	const Eigen::Matrix3d& aCov = a->covariance().get();
	if (disagreementChi2(c.guess, a->scanInRef, prior + aCov) > m_params.gate_chi2)
		return false;
	const Eigen::Matrix3d C = m.cov + aCov + 2 * m_linkNoise.floorCovariance();
	return disagreementChi2(m.scanInRef, a->scanInRef, C) > m_params.gate_chi2 &&
		   m_matcher.explainedFraction(*c.reference, scan, a->scanInRef) >= explained;
}

/* The second opinion on a match that passed the gates (see the header): k's patch agrees
 * (patch_check_keyframes > 0) and no start of the ambiguity check (ambiguity_check) finds a
 * rival. The patch match and the starts are independent matches, run as one loop on the
 * sweep's two threads; the answer does not depend on which thread ran what. */
bool CRevisitLinker::passesChecks(const TSweep& sw, const TKeyframes& keyframes, size_t k,
								  const TCandidate& c, const TScanMatch& m,
								  const Eigen::Matrix3d& prior,
								  const TParallelFor& parallel) const
{
	std::optional<TPatch> patch;
	if (m_params.patch_check_keyframes > 0)
		patch = patchOf(sw, keyframes, k, c.old, m.scanInRef, parallel);
	const TScan2D& scan = keyframes[k].scan;
	std::vector<TPose2D> starts;
	double explained = 0;
	if (m_params.ambiguity_check)
	{
		starts = restartOffsets(m_params.prior_std_xy_m, m_params.prior_std_phi);
		explained = m_matcher.explainedFraction(*c.reference, scan, m.scanInRef);
	}
	std::vector<char> refuses(starts.size() + 1, 0);
	parallel(refuses.size(),
			 [&](size_t i)
			 {
				 refuses[i] = i == 0 ? (patch && !patchAgrees(*patch, m))
									 : rivalFrom(scan, c, m, prior, explained, starts[i - 1]);
			 });
	return std::none_of(refuses.begin(), refuses.end(), [](char r) { return r != 0; });
}

namespace
{
/** [0..1] The share of `ref`'s reduced points that are isolated returns (no line, too few
 * neighbours within 4 normal_radius_m: CReferenceCloud::TAnchor::usable). */
double isolatedShare(const CReferenceCloud& ref)
{
	if (ref.empty()) return 0;
	size_t isolated = 0;
	for (const auto& a : ref.anchors()) isolated += !a.usable;
	return static_cast<double>(isolated) / static_cast<double>(ref.size());
}
}  // namespace

/* One old scan of a long-range laser in a wide hall is mostly isolated returns: a wall 60 m
 * away is sampled every 1.05 m by a 1-degree laser, and a line fit reaches 0.6 m. Matched
 * against it, a revisit explains only its near returns (the crowded hall's north leg: 2-10 %
 * of k's points within 0.1 m at the map's own guess); the old keyframes around it together
 * sample those walls densely (doc/generalisation.md, session 65). */
std::optional<TScanMatch> CRevisitLinker::matchCandidate(const TSweep& sw,
														 const TKeyframes& keyframes, size_t k,
														 TCandidate& c,
														 const TParallelFor& parallel) const
{
	const TScan2D& scan = keyframes[k].scan;
	const auto accepted = [&](const std::optional<TScanMatch>& m)
	{ return m && m->inlierFraction >= m_params.min_inlier_fraction; };
	auto m = m_matcher.match(*c.reference, scan, c.guess);
	if (accepted(m)) return m;
	if (!c.single || !m_params.region_retry ||
		isolatedShare(*c.reference) < m_params.region_min_isolated_share)
		return std::nullopt;
	c.reference = std::make_shared<const CReferenceCloud>(
		oldRegion(sw, keyframes, k, c.old, scan.points, c.guess, parallel, true));
	c.single = false;
	m = m_matcher.match(*c.reference, scan, c.guess);
	return accepted(m) ? m : std::nullopt;
}

size_t CRevisitLinker::linkRevisits(CPoseGraph& graph, const TKeyframes& keyframes) const
{
	const size_t n = graph.numNodes();
	if (n <= m_params.min_index_gap + 1) return 0;
	TSweep sw(graph, m_params.radius_m);
	const Eigen::Matrix3d prior =
		Eigen::Vector3d(m_params.prior_std_xy_m * m_params.prior_std_xy_m,
						m_params.prior_std_xy_m * m_params.prior_std_xy_m,
						m_params.prior_std_phi * m_params.prior_std_phi)
			.asDiagonal();
	// A second thread shares the clouds' line fits and the checks' matches (CSharedLoop:
	// the same links on any number of threads).
	CHelperThread helper;
	const TParallelFor parallel = [&helper](size_t count, const std::function<void(size_t)>& fn)
	{ runShared(helper, count, fn); };
	size_t added = 0;
	// Keyframes stride - 1, 2 stride - 1, ... (counted from node 0, not from the gap: which
	// keyframes are tried does not depend on min_index_gap).
	const size_t s = m_params.stride;
	for (size_t k = (m_params.min_index_gap + 1 + s) / s * s - 1;
		 k < n && !m_stop.stopRequested(); k += s)
	{
		auto c = candidate(sw, keyframes, k, parallel);
		if (!c) continue;
		const auto m = matchCandidate(sw, keyframes, k, *c, parallel);
		if (!m) continue;
		if (!fixesItsHeading(*m)) continue;
		if (disagreementChi2(c->guess, m->scanInRef, prior + m->cov) > m_params.gate_chi2 ||
			!passesChecks(sw, keyframes, k, *c, *m, prior, parallel))
			continue;
		graph.addLink(
			{c->old, k, m->scanInRef,
			 linkInformation(
				 m->cov, denoisedLoopLinkNoise(m_linkNoise, keyframes[k].scan.rangeNoiseStd)),
			 LinkType::LoopClosure});
		sw.linked.insert(pairKey(c->old, k));
		++added;
	}
	return added;
}

}  // namespace lrgc
