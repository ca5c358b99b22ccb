/* CPoseGraph: storage with adjacency, validation of links, MRPT .graph conversion, and a
 * Manhattan-world simulator (see PoseGraph.h). */
#include <lrgc/pose_graph/PoseGraph.h>

#include <mrpt/core/exceptions.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPosePDFGaussianInf.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <random>
#include <unordered_map>

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

mrpt::graphs::CNetworkOfPoses2DInf CPoseGraph::toMrpt() const
{
	mrpt::graphs::CNetworkOfPoses2DInf net;
	for (size_t i = 0; i < m_poses.size(); ++i) net.nodes[i] = mrpt::poses::CPose2D(m_poses[i]);
	for (size_t id = 0; id < m_links.size(); ++id)
	{
		if (!m_enabled[id]) continue;
		const TLink& l = m_links[id];
		mrpt::poses::CPosePDFGaussianInf edge;
		edge.mean = mrpt::poses::CPose2D(l.toInFrom);
		for (int r = 0; r < 3; ++r)
			for (int c = 0; c < 3; ++c) edge.cov_inv(r, c) = l.information(r, c);
		net.insertEdgeAtEnd(l.from, l.to, edge);
	}
	net.root = 0;
	return net;
}

CPoseGraph CPoseGraph::fromMrpt(const mrpt::graphs::CNetworkOfPoses2DInf& net,
								LinkType nonSequentialType)
{
	CPoseGraph g;
	size_t expected = 0;
	for (const auto& [id, p] : net.nodes)  // std::map: ascending ids
	{
		if (id != expected)
			THROW_EXCEPTION_FMT(
				"CPoseGraph::fromMrpt: node ids must be 0..n-1, found id %zu where %zu was "
				"expected",
				static_cast<size_t>(id), expected);
		g.addNode({p.x(), p.y(), p.phi()});
		++expected;
	}
	for (const auto& [ids, e] : net.edges)
	{
		TLink l;
		l.from = ids.first;
		l.to = ids.second;
		l.toInFrom = {e.mean.x(), e.mean.y(), e.mean.phi()};
		for (int r = 0; r < 3; ++r)
			for (int c = 0; c < 3; ++c) l.information(r, c) = e.cov_inv(r, c);
		l.type = (l.to == l.from + 1) ? LinkType::Odometry : nonSequentialType;
		g.addLink(l);
	}
	return g;
}

TSimulatedPoseGraph simulateManhattanPoseGraph(size_t numNodes, size_t gridSide, double sigmaXY,
											   double sigmaPhi, uint32_t seed)
{
	ASSERT_(numNodes >= 1 && gridSide >= 2 && sigmaXY > 0 && sigmaPhi > 0);
	std::mt19937 rng(seed);
	std::normal_distribution<double> n01(0.0, 1.0);
	std::uniform_real_distribution<double> u01(0.0, 1.0);
	const Eigen::Matrix3d info =
		Eigen::Vector3d(1 / (sigmaXY * sigmaXY), 1 / (sigmaXY * sigmaXY),
						1 / (sigmaPhi * sigmaPhi))
			.asDiagonal();
	auto noisy = [&](const TPose2D& truth) {
		return compose(truth, {sigmaXY * n01(rng), sigmaXY * n01(rng), sigmaPhi * n01(rng)});
	};

	TSimulatedPoseGraph out;
	std::unordered_map<long, size_t> lastVisit;  // cell -> latest node there
	long cx = 0, cy = 0;
	int heading = 0;  // multiples of 90 deg
	const long side = static_cast<long>(gridSide);
	const auto cellKey = [side](long x, long y) { return x * side + y; };
	for (size_t i = 0; i < numNodes; ++i)
	{
		const TPose2D truth{double(cx), double(cy), mrpt::math::wrapToPi(heading * M_PI / 2)};
		out.groundTruth.push_back(truth);
		if (i == 0)
			out.graph.addNode(truth);
		else
		{
			const TLink odo{i - 1, i, noisy(between(out.groundTruth[i - 1], truth)), info,
							LinkType::Odometry};
			out.graph.addNode(compose(out.graph.pose(i - 1), odo.toInFrom));
			out.graph.addLink(odo);
		}
		const long key = cellKey(cx, cy);
		if (auto it = lastVisit.find(key); it != lastVisit.end() && it->second + 10 < i)
		{
			const size_t j = it->second;
			out.graph.addLink(
				{j, i, noisy(between(out.groundTruth[j], truth)), info, LinkType::LoopClosure});
			++out.numLoopClosures;
		}
		lastVisit[key] = i;
		// Next move: mostly straight, sometimes turn; never leave the grid.
		const double r = u01(rng);
		if (r < 0.15)
			heading += 1;
		else if (r < 0.30)
			heading += 3;
		for (int attempt = 0; attempt < 6; ++attempt)  // tries every direction
		{
			static const long dx[4] = {1, 0, -1, 0}, dy[4] = {0, 1, 0, -1};
			const int h = ((heading % 4) + 4) % 4;
			const long nx = cx + dx[h], ny = cy + dy[h];
			if (nx >= 0 && ny >= 0 && nx < side && ny < side)
			{
				cx = nx, cy = ny;
				break;
			}
			heading += (attempt == 0 && u01(rng) < 0.5) ? 3 : 1;
		}
		heading = ((heading % 4) + 4) % 4;
	}
	return out;
}

}  // namespace lrgc
