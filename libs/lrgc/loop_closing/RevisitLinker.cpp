#include <lrgc/loop_closing/RevisitLinker.h>

#include <lrgc/scan_matching/ReferenceCloud.h>
#include <lrgc/common/params_io.h>
#include <lrgc/common/se2.h>

#include <mrpt/config/CConfigFileBase.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <optional>
#include <unordered_map>
#include <unordered_set>

namespace lrgc
{
using mrpt::math::TPose2D;

CRevisitLinker::CRevisitLinker(const TRevisitLinkerParams& p, const TScanMatcherParams& matcher,
							   const TLinkNoise& linkNoise)
	: m_params(p), m_matcherParams(matcher), m_linkNoise(linkNoise), m_matcher(matcher)
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

/* k's candidate and the reference to match it against: the nearest old keyframe within
 * radius_m and max_phi, alone; else (any_heading) the nearest within radius_m at any heading,
 * with every old keyframe within 3 radius_m placed around it, cropped to where k's points
 * fall at the guess (as the loop closer's step 3). */
std::optional<CRevisitLinker::TCandidate> CRevisitLinker::candidate(const TSweep& sw,
																	const TKeyframes& keyframes,
																	size_t k) const
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
	c.guess = between(sw.graph.pose(c.old), pk);
	if (same)
	{
		c.reference = CReferenceCloud::fromScan(keyframes[c.old].scan, m_matcherParams);
		return c;
	}
	std::vector<TScan2D> scans;
	std::vector<TPose2D> inOld;
	for (const auto& [j, d] : oldNear(sw, k, 3 * m_params.radius_m))
	{
		scans.push_back(keyframes[j].scan);
		inOld.push_back(between(sw.graph.pose(c.old), sw.graph.pose(j)));
	}
	std::vector<Eigen::Vector2d> kInOld;
	const CPointTransform toOld(c.guess);
	for (const auto& p : keyframes[k].scan.points) kInOld.push_back(toOld(p));
	const double margin =
		m_matcherParams.max_correspondence_dist_m + 4 * m_matcherParams.normal_radius_m + 0.2;
	c.reference = CReferenceCloud::fromScansNear(scans, inOld, m_matcherParams, kInOld, margin);
	return c;
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
	size_t added = 0;
	// Keyframes stride - 1, 2 stride - 1, ... (counted from node 0, not from the gap: which
	// keyframes are tried does not depend on min_index_gap).
	const size_t s = m_params.stride;
	for (size_t k = (m_params.min_index_gap + 1 + s) / s * s - 1;
		 k < n && !m_stop.stopRequested(); k += s)
	{
		const auto c = candidate(sw, keyframes, k);
		if (!c || sw.linkedNear(k, c->old)) continue;
		const auto m = m_matcher.match(c->reference, keyframes[k].scan, c->guess);
		if (!m || m->inlierFraction < m_params.min_inlier_fraction) continue;
		if (disagreementChi2(c->guess, m->scanInRef, prior + m->cov) > m_params.gate_chi2)
			continue;
		graph.addLink({c->old, k, m->scanInRef, linkInformation(m->cov, m_linkNoise),
					   LinkType::LoopClosure});
		sw.linked.insert(pairKey(c->old, k));
		++added;
	}
	return added;
}

}  // namespace lrgc
