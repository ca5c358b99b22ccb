/* CPoseGraph: storage with adjacency, validation of links, MRPT .graph conversion. */
#include <lrgc/pose_graph/PoseGraph.h>

#include <mrpt/core/exceptions.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

#include <lrgc/common/se2.h>

namespace lrgc
{
const char* toString(LinkType t)
{
	switch (t)
	{
		case LinkType::Odometry:
			return "Odometry";
		case LinkType::ScanMatch:
			return "ScanMatch";
		case LinkType::LoopClosure:
			return "LoopClosure";
	}
	return "?";
}

void CPoseGraph::checkNode(size_t node, const char* where) const
{
	if (node >= m_poses.size())
		THROW_EXCEPTION_FMT("CPoseGraph::%s: node index %zu out of range (graph has %zu nodes)",
							where, node, m_poses.size());
}

size_t CPoseGraph::addNode(const mrpt::math::TPose2D& nodeInMap)
{
	if (!std::isfinite(nodeInMap.x) || !std::isfinite(nodeInMap.y) ||
		!std::isfinite(nodeInMap.phi))
		THROW_EXCEPTION_FMT("CPoseGraph::addNode: non-finite pose for node %zu",
							m_poses.size());
	m_poses.push_back({nodeInMap.x, nodeInMap.y, mrpt::math::wrapToPi(nodeInMap.phi)});
	m_adjacency.emplace_back();
	return m_poses.size() - 1;
}

size_t CPoseGraph::addLink(const TLink& link)
{
	const size_t id = m_links.size();
	checkNode(link.from, "addLink(from)");
	checkNode(link.to, "addLink(to)");
	if (link.from == link.to)
		THROW_EXCEPTION_FMT("CPoseGraph::addLink: link %zu joins node %zu to itself", id,
							link.from);
	const auto& z = link.toInFrom;
	if (!std::isfinite(z.x) || !std::isfinite(z.y) || !std::isfinite(z.phi) ||
		!link.information.allFinite())
		THROW_EXCEPTION_FMT(
			"CPoseGraph::addLink: non-finite measurement or information in link %zu (%zu->%zu)",
			id, link.from, link.to);
	const Eigen::Matrix3d& I = link.information;
	if ((I - I.transpose()).cwiseAbs().maxCoeff() >
		1e-9 * std::max(1.0, I.cwiseAbs().maxCoeff()))
		THROW_EXCEPTION_FMT(
			"CPoseGraph::addLink: information of link %zu (%zu->%zu) is not symmetric", id,
			link.from, link.to);
	if (Eigen::LLT<Eigen::Matrix3d>(I).info() != Eigen::Success)
		THROW_EXCEPTION_FMT(
			"CPoseGraph::addLink: information of link %zu (%zu->%zu) is not positive definite",
			id, link.from, link.to);
	TLink stored = link;
	stored.toInFrom.phi = mrpt::math::wrapToPi(z.phi);
	stored.information = 0.5 * (I + I.transpose());
	m_links.push_back(stored);
	m_enabled.push_back(1);
	m_adjacency[link.from].push_back(id);
	m_adjacency[link.to].push_back(id);
	return id;
}

void CPoseGraph::setLinkEnabled(size_t linkId, bool enabled)
{
	link(linkId);  // range check
	m_enabled[linkId] = enabled ? 1 : 0;
}

bool CPoseGraph::isLinkEnabled(size_t linkId) const
{
	link(linkId);
	return m_enabled[linkId] != 0;
}

const mrpt::math::TPose2D& CPoseGraph::pose(size_t node) const
{
	checkNode(node, "pose");
	return m_poses[node];
}

void CPoseGraph::setPose(size_t node, const mrpt::math::TPose2D& nodeInMap)
{
	checkNode(node, "setPose");
	if (!std::isfinite(nodeInMap.x) || !std::isfinite(nodeInMap.y) ||
		!std::isfinite(nodeInMap.phi))
		THROW_EXCEPTION_FMT("CPoseGraph::setPose: non-finite pose for node %zu", node);
	m_poses[node] = {nodeInMap.x, nodeInMap.y, mrpt::math::wrapToPi(nodeInMap.phi)};
	m_lowestMoved = std::min(m_lowestMoved, node);
}

size_t CPoseGraph::lowestJoinedNode(size_t node) const
{
	checkNode(node, "lowestJoinedNode");
	std::vector<uint8_t> seen(m_poses.size(), 0);
	std::vector<size_t> queue{node};
	seen[node] = 1;
	size_t lowest = node;
	for (size_t q = 0; q < queue.size() && lowest > 0; ++q)
		for (const size_t id : m_adjacency[queue[q]])
		{
			if (!m_enabled[id]) continue;
			const size_t other =
				m_links[id].from == queue[q] ? m_links[id].to : m_links[id].from;
			if (seen[other]) continue;
			seen[other] = 1;
			lowest = std::min(lowest, other);
			queue.push_back(other);
		}
	return lowest;
}

size_t CPoseGraph::takeLowestMovedNode()
{
	return std::min(std::exchange(m_lowestMoved, SIZE_MAX), m_poses.size());
}

const TLink& CPoseGraph::link(size_t linkId) const
{
	if (linkId >= m_links.size())
		THROW_EXCEPTION_FMT("CPoseGraph: link id %zu out of range (graph has %zu links)",
							linkId, m_links.size());
	return m_links[linkId];
}

const std::vector<size_t>& CPoseGraph::linksOf(size_t node) const
{
	checkNode(node, "linksOf");
	return m_adjacency[node];
}

std::vector<std::vector<size_t>> visitsOf(std::vector<size_t> nodes, size_t maxGap)
{
	std::sort(nodes.begin(), nodes.end());
	std::vector<std::vector<size_t>> visits;
	for (const size_t j : nodes)
	{
		if (visits.empty() || j > visits.back().back() + maxGap) visits.emplace_back();
		visits.back().push_back(j);
	}
	return visits;
}

}  // namespace lrgc
