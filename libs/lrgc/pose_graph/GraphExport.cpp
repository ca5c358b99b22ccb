#include <lrgc/pose_graph/GraphExport.h>

#include <lrgc/common/se2.h>
#include <lrgc/pose_graph/PoseGraphOptimizer.h>
#include <lrgc/pose_graph/PoseGraphProblem.h>

#include <mrpt/core/exceptions.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPosePDFGaussianInf.h>

#include <Eigen/Dense>
#include <map>
#include <utility>
#include <vector>

namespace lrgc
{
namespace
{
struct TOrientedLink
{
	TPose2D z;  //!< (a <- b)
	Eigen::Matrix3d information;
};

// Information the least-squares optimum saw: s^2 Omega for a robust loop link (DCS scale at
// the current poses), Omega otherwise.
Eigen::Matrix3d effectiveInformation(const CPoseGraph& g, const TLink& l,
									 const TPoseGraphOptimizerParams& p)
{
	if (!p.robust_loop_closures || l.type != LinkType::LoopClosure) return l.information;
	const Eigen::Vector3d e = linkResidual(g.pose(l.from), g.pose(l.to), l.toInFrom);
	const double s = detail::TCostKernel::scale(e.dot(l.information * e), p.dcs_phi);
	return s * s * l.information;
}

// The link turned around: Z^-1 with Ad_Z^-T Omega Ad_Z^-1 (file comment).
TOrientedLink reversed(const TPose2D& z, const Eigen::Matrix3d& information)
{
	const double c = std::cos(z.phi), s = std::sin(z.phi);
	Eigen::Matrix3d ad;
	ad << c, -s, z.y, s, c, -z.x, 0, 0, 1;
	const Eigen::Matrix3d adInv = ad.inverse();
	Eigen::Matrix3d info = adInv.transpose() * information * adInv;
	info = 0.5 * (info + info.transpose());
	return {inverse(z), info};
}

TOrientedLink fuse(const std::vector<TOrientedLink>& links)
{
	const TPose2D& z1 = links.front().z;
	Eigen::Matrix3d info = Eigen::Matrix3d::Zero();
	Eigen::Vector3d weighted = Eigen::Vector3d::Zero();
	for (const auto& l : links)
	{
		info += l.information;
		weighted += l.information * toVector(between(z1, l.z));  // angle wrapped to (-pi, pi]
	}
	const Eigen::Vector3d d = info.ldlt().solve(weighted);
	return {compose(z1, TPose2D(d.x(), d.y(), d.z())), info};
}

/** The network's nodes: g's poses (VERTEX_SE2), node ids the indices; root = node 0. */
mrpt::graphs::CNetworkOfPoses2DInf nodesOf(const CPoseGraph& g)
{
	mrpt::graphs::CNetworkOfPoses2DInf net;
	for (size_t i = 0; i < g.numNodes(); ++i) net.nodes[i] = mrpt::poses::CPose2D(g.pose(i));
	net.root = 0;
	return net;
}

/** One EDGE_SE2: z = (a <- b) with its information. */
void addEdge(mrpt::graphs::CNetworkOfPoses2DInf& net, size_t a, size_t b, const TPose2D& z,
			 const Eigen::Matrix3d& information)
{
	mrpt::poses::CPosePDFGaussianInf edge;
	edge.mean = mrpt::poses::CPose2D(z);
	for (int r = 0; r < 3; ++r)
		for (int c = 0; c < 3; ++c) edge.cov_inv(r, c) = information(r, c);
	net.insertEdgeAtEnd(a, b, edge);
}
}  // namespace

mrpt::graphs::CNetworkOfPoses2DInf toMrptLeastSquares(const CPoseGraph& g,
													  const TPoseGraphOptimizerParams& params)
{
	std::map<std::pair<size_t, size_t>, std::vector<TOrientedLink>> pairs;
	for (size_t id = 0; id < g.numLinks(); ++id)
	{
		if (!g.isLinkEnabled(id)) continue;
		const TLink& l = g.link(id);
		const Eigen::Matrix3d info = effectiveInformation(g, l, params);
		if (l.from < l.to)
			pairs[{l.from, l.to}].push_back({l.toInFrom, info});
		else
			pairs[{l.to, l.from}].push_back(reversed(l.toInFrom, info));
	}
	mrpt::graphs::CNetworkOfPoses2DInf net = nodesOf(g);
	for (const auto& [ends, links] : pairs)
	{
		const TOrientedLink f = links.size() == 1 ? links.front() : fuse(links);
		addEdge(net, ends.first, ends.second, f.z, f.information);
	}
	return net;
}

mrpt::graphs::CNetworkOfPoses2DInf toMrpt(const CPoseGraph& g)
{
	mrpt::graphs::CNetworkOfPoses2DInf net = nodesOf(g);
	for (size_t id = 0; id < g.numLinks(); ++id)
	{
		if (!g.isLinkEnabled(id)) continue;
		const TLink& l = g.link(id);
		addEdge(net, l.from, l.to, l.toInFrom, l.information);
	}
	return net;
}

CPoseGraph poseGraphFromMrpt(const mrpt::graphs::CNetworkOfPoses2DInf& net,
							 LinkType nonSequentialType)
{
	CPoseGraph g;
	size_t expected = 0;
	for (const auto& [id, p] : net.nodes)  // std::map: ascending ids
	{
		if (id != expected)
			THROW_EXCEPTION_FMT(
				"poseGraphFromMrpt: node ids must be 0..n-1, found id %zu where %zu was "
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

}  // namespace lrgc
