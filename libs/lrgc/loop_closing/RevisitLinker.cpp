#include <lrgc/loop_closing/RevisitLinker.h>

#include <lrgc/scan_matching/ReferenceCloud.h>
#include <lrgc/common/params_io.h>
#include <lrgc/common/se2.h>

#include <mrpt/config/CConfigFileBase.h>

#include <Eigen/Dense>
#include <cmath>
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

size_t CRevisitLinker::linkRevisits(CPoseGraph& graph, const TKeyframes& keyframes) const
{
	const size_t n = graph.numNodes();
	if (n <= m_params.min_index_gap + 1) return 0;
	const double r = m_params.radius_m;
	// Existing links, and a hash grid (cells of side r) over the keyframe positions.
	std::unordered_set<uint64_t> linked;
	for (size_t id = 0; id < graph.numLinks(); ++id)
		if (graph.isLinkEnabled(id))
			linked.insert(pairKey(graph.link(id).from, graph.link(id).to));
	std::unordered_map<uint64_t, std::vector<size_t>> cells;
	auto cellOf = [r](const TPose2D& p) {
		return std::pair{int64_t(std::floor(p.x / r)), int64_t(std::floor(p.y / r))};
	};
	for (size_t j = 0; j < n; ++j)
	{
		const auto [ix, iy] = cellOf(graph.pose(j));
		cells[cellKey(ix, iy)].push_back(j);
	}
	auto linkedNear = [&](size_t k, size_t j)
	{
		for (size_t a = k > 2 ? k - 2 : 0; a <= std::min(n - 1, k + 2); ++a)
			for (size_t b = j > 2 ? j - 2 : 0; b <= std::min(n - 1, j + 2); ++b)
				if (linked.count(pairKey(a, b))) return true;
		return false;
	};
	const Eigen::Matrix3d prior =
		Eigen::Vector3d(m_params.prior_std_xy_m * m_params.prior_std_xy_m,
						m_params.prior_std_xy_m * m_params.prior_std_xy_m,
						m_params.prior_std_phi * m_params.prior_std_phi)
			.asDiagonal();

	size_t added = 0;
	for (size_t k = m_params.min_index_gap + 1; k < n && !m_stop.stopRequested();
		 k += m_params.stride)
	{
		const TPose2D pk = graph.pose(k);
		// The nearest old keyframe within the radius and the heading limit.
		size_t best = n;
		double bestD = r;
		const auto [cx, cy] = cellOf(pk);
		for (int64_t dx = -1; dx <= 1; ++dx)
			for (int64_t dy = -1; dy <= 1; ++dy)
			{
				const auto it = cells.find(cellKey(cx + dx, cy + dy));
				if (it == cells.end()) continue;
				for (const size_t j : it->second)
				{
					if (j + m_params.min_index_gap >= k || (j < m_split) != (k < m_split))
						continue;
					const TPose2D pj = graph.pose(j);
					const double d = std::hypot(pj.x - pk.x, pj.y - pk.y);
					if (d < bestD &&
						std::abs(mrpt::math::wrapToPi(pj.phi - pk.phi)) <= m_params.max_phi)
						best = j, bestD = d;
				}
			}
		if (best == n || linkedNear(k, best)) continue;
		const TPose2D guess = between(graph.pose(best), pk);
		const auto m =
			m_matcher.match(CReferenceCloud::fromScan(keyframes[best].scan, m_matcherParams),
							keyframes[k].scan, guess);
		if (!m || m->inlierFraction < m_params.min_inlier_fraction) continue;
		if (disagreementChi2(guess, m->scanInRef, prior + m->cov) > m_params.gate_chi2)
			continue;
		graph.addLink({best, k, m->scanInRef, linkInformation(m->cov, m_linkNoise),
					   LinkType::LoopClosure});
		linked.insert(pairKey(best, k));
		++added;
	}
	return added;
}

}  // namespace lrgc
