/* Problem extraction and normal-equation assembly for CPoseGraphOptimizer (see
 * PoseGraphProblem.h). */
#include "PoseGraphProblem.h"

#include <mrpt/core/exceptions.h>

#include <algorithm>
#include <numeric>
#include <unordered_map>

#include <lrgc/pose_graph/PoseGraphOptimizer.h>

namespace lrgc::detail
{
using mrpt::math::TPose2D;

void TProblem::addLink(const CPoseGraph& g, size_t id, int vi, int vj)
{
	const TLink& l = g.link(id);
	TProblemLink pl;
	pl.id = id;
	pl.vi = vi;
	pl.vj = vj;
	if (vi < 0) pl.fixedFrom = g.pose(l.from);
	if (vj < 0) pl.fixedTo = g.pose(l.to);
	pl.z = l.toInFrom;
	pl.info = l.information;
	pl.loopClosure = l.type == LinkType::LoopClosure;
	links.push_back(pl);
}

TProblem TProblem::wholeGraph(const CPoseGraph& g, size_t anchor, size_t frozenBelow)
{
	// Breadth-first search from the anchor over enabled links: its connected component.
	const size_t n = g.numNodes();
	std::vector<uint8_t> reached(n, 0);
	std::vector<size_t> queue{anchor};
	reached[anchor] = 1;
	for (size_t head = 0; head < queue.size(); ++head)
		for (size_t id : g.linksOf(queue[head]))
		{
			if (!g.isLinkEnabled(id)) continue;
			const TLink& l = g.link(id);
			const size_t other = l.from == queue[head] ? l.to : l.from;
			if (!reached[other]) reached[other] = 1, queue.push_back(other);
		}
	TProblem p;
	std::vector<int> varOf(n, -1);
	for (size_t i = 0; i < n; ++i)
		if (reached[i] && i != anchor && i >= frozenBelow)
		{
			varOf[i] = static_cast<int>(p.varNode.size());
			p.varNode.push_back(i);
			p.x.push_back(g.pose(i));
		}
	for (size_t id = 0; id < g.numLinks(); ++id)
	{
		const TLink& l = g.link(id);
		if (g.isLinkEnabled(id) && reached[l.from])
			p.addLink(g, id, varOf[l.from], varOf[l.to]);
	}
	return p;
}

TProblem TProblem::subset(const CPoseGraph& g, const std::vector<size_t>& freeNodes)
{
	TProblem p;
	std::unordered_map<size_t, int> varOf;
	varOf.reserve(freeNodes.size() * 2);
	for (size_t node : freeNodes)
	{
		if (node >= g.numNodes())
			THROW_EXCEPTION_FMT(
				"CPoseGraphOptimizer::optimizeSubset: free node %zu out of range (graph has "
				"%zu "
				"nodes)",
				node, g.numNodes());
		if (!varOf.emplace(node, static_cast<int>(p.varNode.size())).second)
			THROW_EXCEPTION_FMT("CPoseGraphOptimizer::optimizeSubset: node %zu listed twice",
								node);
		p.varNode.push_back(node);
		p.x.push_back(g.pose(node));
	}
	// Union-find over the free nodes: each group must be tied to a fixed node.
	std::vector<int> parent(freeNodes.size());
	std::iota(parent.begin(), parent.end(), 0);
	std::vector<uint8_t> anchored(freeNodes.size(), 0);
	const auto root = [&parent](int a)
	{
		while (parent[a] != a) a = parent[a] = parent[parent[a]];
		return a;
	};
	const auto varIndex = [&varOf](size_t node)
	{
		const auto it = varOf.find(node);
		return it == varOf.end() ? -1 : it->second;
	};
	for (size_t k = 0; k < freeNodes.size(); ++k)
		for (size_t id : g.linksOf(freeNodes[k]))
		{
			if (!g.isLinkEnabled(id)) continue;
			const TLink& l = g.link(id);
			const int vi = varIndex(l.from), vj = varIndex(l.to);
			if (vi >= 0 && vj >= 0)
			{
				if (l.from != freeNodes[k]) continue;  // taken once, from its `from` end
				parent[root(vi)] = root(vj);
			}
			else
				anchored[k] = 1;
			p.addLink(g, id, vi, vj);
		}
	for (size_t k = 0; k < freeNodes.size(); ++k)
		if (anchored[k]) anchored[root(static_cast<int>(k))] = 1;
	for (size_t k = 0; k < freeNodes.size(); ++k)
		if (!anchored[root(static_cast<int>(k))])
			THROW_EXCEPTION_FMT(
				"CPoseGraphOptimizer::optimizeSubset: free node %zu has no chain of enabled "
				"links "
				"to a fixed node, so its pose is undetermined",
				freeNodes[k]);
	return p;
}

double TProblem::evaluate(const std::vector<TPose2D>& xs, const TCostKernel& k,
						  double* cost) const
{
	double chi2 = 0, robust = 0;
	for (const TProblemLink& l : links)
	{
		const TPose2D& a = l.vi >= 0 ? xs[l.vi] : l.fixedFrom;
		const TPose2D& b = l.vj >= 0 ? xs[l.vj] : l.fixedTo;
		const Eigen::Vector3d e = linkResidual(a, b, l.z);
		const double c = e.dot(l.info * e);
		chi2 += c;
		robust += (k.robust && l.loopClosure) ? k.cost(c, k.phiFor(l.phiStart)) : c;
	}
	if (cost) *cost = robust;
	return chi2;
}

void TProblem::buildPattern(TNormalEquations& ne)
{
	// Block column b holds the blocks (a, b) with a < b joined by a link, then (b, b).
	const size_t m = varNode.size();
	std::vector<std::vector<int>> above(m);
	for (const TProblemLink& l : links)
		if (l.vi >= 0 && l.vj >= 0) above[std::max(l.vi, l.vj)].push_back(std::min(l.vi, l.vj));
	for (auto& col : above)
	{
		std::sort(col.begin(), col.end());
		col.erase(std::unique(col.begin(), col.end()), col.end());
	}
	for (TProblemLink& l : links)
		if (l.vi >= 0 && l.vj >= 0)
		{
			const auto& col = above[std::max(l.vi, l.vj)];
			l.offBlock = static_cast<int>(
				std::lower_bound(col.begin(), col.end(), std::min(l.vi, l.vj)) - col.begin());
		}
	ne.blockColPtr.assign(m + 1, 0);
	ne.blockRowIdx.clear();
	for (size_t b = 0; b < m; ++b)
	{
		ne.blockColPtr[b] = static_cast<int>(ne.blockRowIdx.size());
		ne.blockRowIdx.insert(ne.blockRowIdx.end(), above[b].begin(), above[b].end());
		ne.blockRowIdx.push_back(static_cast<int>(b));
	}
	ne.blockColPtr[m] = static_cast<int>(ne.blockRowIdx.size());
	ne.colPtr.assign(3 * m + 1, 0);
	ne.diagPos.assign(3 * m, 0);
	ne.rowIdx.clear();
	for (size_t b = 0; b < m; ++b)
		for (int c = 0; c < 3; ++c)
		{
			const size_t col = 3 * b + c;
			ne.colPtr[col] = static_cast<int>(ne.rowIdx.size());
			for (int a : above[b])
				for (int r = 0; r < 3; ++r) ne.rowIdx.push_back(3 * a + r);
			for (int r = 0; r <= c; ++r) ne.rowIdx.push_back(static_cast<int>(3 * b) + r);
			ne.diagPos[col] = static_cast<int>(ne.rowIdx.size()) - 1;
		}
	ne.colPtr[3 * m] = static_cast<int>(ne.rowIdx.size());
	ne.values.assign(ne.rowIdx.size(), 0.0);
	m_patternBuilt = true;
}

void TProblem::linearize(const TCostKernel& k, TNormalEquations& ne)
{
	if (!m_patternBuilt) buildPattern(ne);
	std::fill(ne.values.begin(), ne.values.end(), 0.0);
	ne.rhs.setZero(3 * static_cast<Eigen::Index>(varNode.size()));
	// Adds M (3x3) into block (a, b), a <= b, upper triangle only when a == b.
	const auto addDiag = [&ne](int v, const Eigen::Matrix3d& M)
	{
		for (int c = 0; c < 3; ++c)
		{
			const int base = ne.diagPos[3 * v + c] - c;  // position of H(3v, 3v + c)
			for (int r = 0; r <= c; ++r) ne.values[base + r] += M(r, c);
		}
	};
	const auto addOff = [&ne](int a, int b, int blockIdx, const Eigen::Matrix3d& M)
	{
		for (int c = 0; c < 3; ++c)
		{
			const int base = ne.colPtr[3 * b + c] + 3 * blockIdx;
			for (int r = 0; r < 3; ++r) ne.values[base + r] += M(r, c);
		}
	};
	Eigen::Matrix3d Ji, Jj;
	for (const TProblemLink& l : links)
	{
		const TPose2D& a = l.vi >= 0 ? x[l.vi] : l.fixedFrom;
		const TPose2D& b = l.vj >= 0 ? x[l.vj] : l.fixedTo;
		const Eigen::Vector3d e = linkResidual(a, b, l.z, &Ji, &Jj);
		double w = 1.0;
		if (k.robust && l.loopClosure)
		{
			const double s = k.scale(e.dot(l.info * e), k.phiFor(l.phiStart));
			w = s * s;
		}
		const Eigen::Matrix3d W = w * l.info;
		const Eigen::Vector3d We = W * e;
		const Eigen::Matrix3d WJi = W * Ji, WJj = W * Jj;
		if (l.vi >= 0)
		{
			addDiag(l.vi, Ji.transpose() * WJi);
			ne.rhs.segment<3>(3 * l.vi) += Ji.transpose() * We;
		}
		if (l.vj >= 0)
		{
			addDiag(l.vj, Jj.transpose() * WJj);
			ne.rhs.segment<3>(3 * l.vj) += Jj.transpose() * We;
		}
		if (l.vi >= 0 && l.vj >= 0)
		{
			if (l.vi < l.vj)
				addOff(l.vi, l.vj, l.offBlock, Ji.transpose() * WJj);
			else
				addOff(l.vj, l.vi, l.offBlock, Jj.transpose() * WJi);
		}
	}
}

std::vector<size_t> TProblem::rejectedLoopLinks(const TCostKernel& k, double reject_scale) const
{
	std::vector<size_t> out;
	if (!k.robust) return out;
	for (const TProblemLink& l : links)
	{
		if (!l.loopClosure) continue;
		const TPose2D& a = l.vi >= 0 ? x[l.vi] : l.fixedFrom;
		const TPose2D& b = l.vj >= 0 ? x[l.vj] : l.fixedTo;
		const Eigen::Vector3d e = linkResidual(a, b, l.z);
		if (k.scale(e.dot(l.info * e), k.phi) < reject_scale) out.push_back(l.id);
	}
	std::sort(out.begin(), out.end());
	return out;
}

Eigen::Vector3d TProblem::residual(const TProblemLink& l, Eigen::Matrix3d* Ji,
								   Eigen::Matrix3d* Jj) const
{
	const TPose2D& a = l.vi >= 0 ? x[l.vi] : l.fixedFrom;
	const TPose2D& b = l.vj >= 0 ? x[l.vj] : l.fixedTo;
	return linkResidual(a, b, l.z, Ji, Jj);
}

void TProblem::writeBack(CPoseGraph& g) const
{
	for (size_t k = 0; k < varNode.size(); ++k) g.setPose(varNode[k], x[k]);
}

}  // namespace lrgc::detail
