/* CLoopCloser, step 1's uncertainty (see LoopCloser.h): the relative covariance of every
 * old node, by a propagation over the whole graph (UncertaintyPropagation.h) or by reuse of
 * the last one ([LoopCloser] gate_reuse_keyframes). */
#include <lrgc/loop_closing/LoopCloser.h>

#include <algorithm>
#include <vector>

namespace lrgc
{
using mrpt::math::TPose2D;

TStepModel CLoopCloser::stepModel() const
{
	TStepModel m;
	m.fuseParallelLinks = m_params.gate_fuse_links;
	m.driftXY = m_params.gate_drift_xy_m2_per_m;
	return m;
}

std::vector<TRelativeUncertainty> CLoopCloser::relativeUncertainty(const CPoseGraph& graph,
																   size_t newest)
{
	if (auto reused = reuseGate(graph, newest))
	{
		++m_stats.gateReuses;
		m_stats.work.gateReusedLabels += reused->size();
		return std::move(*reused);
	}
	++m_stats.gatePropagations;
	m_stats.work.gatePropagatedNodes += graph.numNodes();
	progress();
	const auto& poses = graph.poses();
	m_gateCache = TGateCache{newest,
							 graph.numLinks(),
							 {poses.begin(), poses.begin() + newest + 1},
							 propagateUncertainty(graph, newest, {}, stepModel())};
	return m_gateCache->labels;
}

// Reuse of the anchor a's propagation for keyframe n > a: every path from n into the graph
// behind a enters it through the newest keyframes around a, so
//     (n <- v) = (n <- a) (+) (a <- v),   C_nv = J1 C_na J1^T + J2 C_av J2^T
// with (n <- a) from a Dijkstra from n stopped at a (the nodes it settles first keep their
// own labels). Valid while the graph behind a is as it was: no pose of the old map
// (0..a - old_map_exclusion_keyframes) moved (the Jacobians), no loop link (a shorter path that
// bypasses a) and no link reaching further back than a - old_map_exclusion_keyframes.
// Otherwise, or after gate_reuse_keyframes keyframes: nullopt.
std::optional<std::vector<TRelativeUncertainty>> CLoopCloser::reuseGate(const CPoseGraph& graph,
																		size_t newest) const
{
	if (!m_gateCache || m_params.gate_reuse_keyframes == 0) return std::nullopt;
	const TGateCache& c = *m_gateCache;
	if (newest <= c.anchor || newest - c.anchor > m_params.gate_reuse_keyframes)
		return std::nullopt;
	const auto samePose = [](const TPose2D& p, const TPose2D& q)
	{ return p.x == q.x && p.y == q.y && p.phi == q.phi; };
	// Local registration keeps adjusting the newest keyframes around a (its window); their
	// moves are millimetres and change the Jacobians along the paths only that much.
	const size_t settled =
		c.anchor + 1 - std::min(c.anchor + 1, m_params.old_map_exclusion_keyframes);
	if (!std::equal(c.poses.begin(), c.poses.begin() + settled, graph.poses().begin(),
					samePose))
		return std::nullopt;
	for (size_t id = c.links; id < graph.numLinks(); ++id)
	{
		const TLink& l = graph.link(id);
		if (l.type == LinkType::LoopClosure ||
			std::min(l.from, l.to) + m_params.old_map_exclusion_keyframes <= c.anchor)
			return std::nullopt;
	}
	TUncertaintyLimits toAnchor;
	toAnchor.stopAtNode = c.anchor;
	std::vector<TRelativeUncertainty> out =
		propagateUncertainty(graph, newest, toAnchor, stepModel());
	if (out.back().node != c.anchor) return std::nullopt;  // not connected to the anchor
	const TRelativeUncertainty anchorInNewest = out.back();
	std::vector<char> reached(graph.numNodes(), 0);
	for (const auto& r : out) reached[r.node] = 1;
	for (const auto& r : c.labels)
		if (!reached[r.node]) out.push_back(chainUncertainty(anchorInNewest, r));
	return out;
}

}  // namespace lrgc
