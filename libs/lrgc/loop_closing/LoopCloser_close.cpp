/* CLoopCloser, step 4 (see LoopCloser.h): a loop match held until an independent one agrees
 * where the gate is very uncertain, then the link added and, where it disagrees with the
 * current estimate, the whole graph solved with robust loop links (paper 2.2: the patch
 * keyframes then re-matched, rematch() in LoopCloser_match.cpp). */
#include <lrgc/common/CpuTime.h>
#include <lrgc/common/se2.h>
#include <lrgc/loop_closing/LoopCloser.h>

#include <mrpt/math/wrap2pi.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

namespace lrgc
{
using mrpt::math::TPose2D;

namespace
{
/** Two held loop matches agree when the pose of the newer new node they imply differs by at
 * most kAgreeXY [m] plus kAgreePerMetre of the path between the new nodes, and kAgreeTheta
 * [rad]: scan-matched loop links are good to centimetres, local chains to ~1 %. */
constexpr double kAgreeXY = 0.3, kAgreePerMetre = 0.02, kAgreeTheta = 2.0 * M_PI / 180;
}  // namespace

/* Held link a (oa <- na) and new link b (ob <- nb), na before nb. Via a, nb in oa's frame is
 * Z_a (+) (na <- nb) (new side, from the graph); via b it is (oa <- ob) (+) Z_b (old side).
 * Both sides of the graph are locally consistent; only the loop itself is in doubt. */
bool CLoopCloser::matchesAgree(const CPoseGraph& g, const TLink& a, const TLink& b)
{
	const TPose2D newSide = between(g.pose(a.to), g.pose(b.to));
	const TPose2D viaA = compose(a.toInFrom, newSide);
	const TPose2D viaB = compose(between(g.pose(a.from), g.pose(b.from)), b.toInFrom);
	const TPose2D d = between(viaA, viaB);
	return translationNorm(d) <= kAgreeXY + kAgreePerMetre * translationNorm(newSide) &&
		   std::abs(mrpt::math::wrapToPi(d.phi)) <= kAgreeTheta;
}

// With a very uncertain gate (std > confirm_above_sigma_m) a match is held until a later match
// from a disjoint patch agrees with it. Returns false while the match is held (or dropped);
// true to go on, with the confirmed held link added to the graph (`heldId`, vetted or not).
bool CLoopCloser::confirmed(CPoseGraph& graph, const TCandidates& c, const TSearchWindow& w,
							const TLoopMatch& m, std::optional<size_t>& heldId,
							std::vector<size_t>& vettedLinks)
{
	const size_t newest = m.link.to;
	if (m_held && newest > m_held->link.to + 2 * m_params.old_map_exclusion_keyframes)
		m_held.reset(), ++m_stats.unconfirmed;  // no agreeing match came in time
	if (m_params.confirm_above_sigma_m <= 0 || c.sigmaXY <= m_params.confirm_above_sigma_m)
		return true;
	if (m_held && m_held->link.to >= w.patchFirst) return false;  // same evidence
	if (!m_held || !matchesAgree(graph, m_held->link, m.link))
	{
		if (m_held) ++m_stats.unconfirmed;
		m_held = THeldMatch{m.link, m.vetted};
		++m_stats.heldForConfirmation;
		m_lastRejection = "match held until a later, independent match agrees";
		return false;
	}
	heldId = graph.addLink(m_held->link);
	if (m_held->vetted) vettedLinks.push_back(*heldId);
	m_held.reset();
	return true;
}

// Step 4: add the link; if it disagrees with the current estimate, optimise the whole graph
// with robust loop links: a link the back-end down-weights is disabled and the closure
// rejected; else the patch keyframes are re-matched against the old map (paper 2.2) and the
// graph optimised again.
std::optional<TLoopClosure> CLoopCloser::closeLoop(CPoseGraph& graph, const TScanRefs& scans,
												   const TCandidates& c, const TSearchWindow& w,
												   const TLoopMatch& m)
{
	std::vector<size_t> vettedLinks;
	std::optional<size_t> heldId;  // a held match confirmed: its link goes in first
	if (!confirmed(graph, c, w, m, heldId, vettedLinks)) return std::nullopt;
	return addAndClose(graph, scans, c, w, m, heldId, vettedLinks);
}

std::optional<TLoopClosure> CLoopCloser::addAndClose(
	CPoseGraph& graph, const TScanRefs& scans, const TCandidates& c, const TSearchWindow& w,
	const TLoopMatch& m, std::optional<size_t> heldId, std::vector<size_t>& vettedLinks)
{
	TLoopClosure lc;
	lc.score = m.score;
	lc.ambiguity = m.ambiguity;
	lc.oldNode = m.link.from;
	lc.newNode = m.link.to;
	lc.linkId = graph.addLink(m.link);
	if (m.vetted) vettedLinks.push_back(lc.linkId);
	const Eigen::Vector3d e =
		linkResidual(graph.pose(lc.oldNode), graph.pose(lc.newNode), m.link.toInFrom);
	if (heldId || e.dot(m.info * e) > m_params.consistent_chi2)
	{
		CCpuTimer closeTimer(m_stats.closeCpuSeconds);
		const auto report = optimize(graph, vettedLinks);
		++m_stats.optimizations;
		if (report.stopped && stopped())
		{  // the graph as it was: the poses unmoved (optimize), the links off
			graph.setLinkEnabled(lc.linkId, false);
			if (heldId) graph.setLinkEnabled(*heldId, false);
			return std::nullopt;
		}
		const auto downweighted = [&](size_t id)
		{
			return std::binary_search(report.downweightedLinks.begin(),
									  report.downweightedLinks.end(), id);
		};
		if (downweighted(lc.linkId) || (heldId && downweighted(*heldId)))
		{
			++m_stats.rejectedByBackEnd;
			m_lastRejection = "loop link down-weighted by the robust back-end";
			graph.setLinkEnabled(lc.linkId, false);
			if (heldId) graph.setLinkEnabled(*heldId, false);
			m_gateCache.reset();  // a path it used may be gone
			optimize(graph);
			return std::nullopt;
		}
		lc.optimized = true;
		lc.rematchLinks = rematch(graph, scans, c, w.patchFirst, lc.newNode, m.doubt);
		if (lc.rematchLinks > 0) optimize(graph), ++m_stats.optimizations;
	}
	++m_stats.accepted;
	m_onKnownGround = !lc.optimized;
	return lc;
}

TOptimizationReport CLoopCloser::optimize(CPoseGraph& graph, const std::vector<size_t>& vetted)
{
	// Counted before the work, so that the worker's published progress stays a lower bound
	// of the job's modelled work: the problem's size (every node and link), then each
	// iteration as it starts.
	const double elements = double(graph.numNodes() + graph.numLinks());
	work().solveElements += elements;
	progress();
	m_optimizer.setIterationCallback(
		[this, elements]
		{
			work().solveIterationElements += elements;
			progress();
		});
	const std::vector<TPose2D> before = graph.poses();  // n poses: little beside a solve
	// Node 0 held fixed; in a piece not yet joined to the map (a session mapped in its own
	// frame, CMetricMapBuilderLRGC::startPiece) the piece's first node, which is 0 otherwise.
	const size_t fixed = graph.lowestJoinedNode(graph.numNodes() - 1);
	const TOptimizationReport r = m_optimizer.optimize(graph, fixed, vetted, m_frozen);
	m_optimizer.setIterationCallback({});
	if (r.stopped)
		for (size_t i = 0; i < before.size(); ++i) graph.setPose(i, before[i]);
	return r;
}

}  // namespace lrgc
