#include <lrgc/localization/ViewContradiction.h>

#include <lrgc/common/se2.h>

#include <algorithm>
#include <utility>

namespace lrgc
{
CViewContradiction::CViewContradiction(const CPoseGraph& map, const TKeyframes& keyframes,
									   const TScanMatcherParams& params)
	: m_map(map), m_keyframes(keyframes), m_params(params)
{
}

std::vector<std::vector<size_t>> CViewContradiction::passesOf(std::vector<size_t> nodes)
{
	std::sort(nodes.begin(), nodes.end());
	std::vector<std::vector<size_t>> passes;
	for (size_t k = 0; k < nodes.size(); ++k)
	{
		if (k == 0 || nodes[k] > nodes[k - 1] + kPassGap) passes.emplace_back();
		passes.back().push_back(nodes[k]);
	}
	std::vector<std::vector<size_t>> kept;
	for (auto& p : passes)
		for (size_t b = 0; b + kMinPassKeyframes <= p.size();)
		{
			// At most kMaxPassKeyframes, but a remainder too short to ask joins this one.
			size_t e = std::min(p.size(), b + kMaxPassKeyframes);
			if (p.size() - e < kMinPassKeyframes) e = p.size();
			kept.emplace_back(p.begin() + long(b), p.begin() + long(e));
			b = e;
		}
	return kept;
}

bool CViewContradiction::contradictsEveryPass(const TScan2D& scan,
											  const mrpt::math::TPose2D& pose,
											  const std::vector<size_t>& nodes, double margin,
											  double fraction)
{
	const auto passes = passesOf(nodes);
	if (m_passes.size() + passes.size() > kMaxCachedPasses) m_passes.clear();
	for (const auto& p : passes)
	{
		const auto& [cloud, cloudInMap] = cloudOf(p);
		if (cloud.freeSpaceViolation(scan, between(cloudInMap, pose), margin) < fraction)
			return false;
	}
	return true;
}

const std::pair<CReferenceCloud, mrpt::math::TPose2D>& CViewContradiction::cloudOf(
	const std::vector<size_t>& pass)
{
	auto it = m_passes.find(pass);
	if (it != m_passes.end()) return it->second;
	const mrpt::math::TPose2D origin = m_map.pose(pass.front());
	std::vector<TScan2D> scans;
	std::vector<mrpt::math::TPose2D> inOrigin;
	for (const size_t i : pass)
		scans.push_back(m_keyframes[i].scan),
			inOrigin.push_back(between(origin, m_map.pose(i)));
	return m_passes
		.emplace(pass, std::pair{CReferenceCloud::fromScans(scans, inOrigin, m_params), origin})
		.first->second;
}

}  // namespace lrgc
