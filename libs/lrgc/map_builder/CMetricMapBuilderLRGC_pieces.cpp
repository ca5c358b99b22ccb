/* CMetricMapBuilderLRGC: maps of several pieces (issue 29).
 *
 * A log continuing a saved map may start where the map has no ground, or where its start
 * cannot be told yet. Rather than hold its scans back until global correlation places it, the
 * session is mapped from its first scan as a piece of its own: its first scan is a keyframe
 * at its odometry pose (the identity without odometry), linked to nothing, and local
 * registration, loop closing (the gate reaches only the nodes joined to the newest, and the
 * optimiser holds the piece's first node fixed) and keyframe reuse (no keyframe of the map is
 * a candidate) work within the piece. The map's keyframes and the piece's share one graph and
 * one index range (the piece's from pieceFirstNode() on), in two frames.
 *
 * When global correlation finds the piece's keyframe k in the map at Z (CPieceJoiner, beside
 * mapping), joinPiece() makes them one map: the loop results in hand are applied (they were
 * computed in the piece's frame), a scan match of k against the map's keyframes around Z
 * refines it to Z', every node of the piece moves by
 *     (map <- piece) = Z' (+) X_k^-1,    X_i <- (map <- piece) (+) X_i,
 * (the scans hang from their keyframes and follow), and a loop link ties k to the nearest map
 * keyframe. Then the joined map is re-matched (the paper's re-matching after a loop closure,
 * 2.2): CRevisitLinker's sweep, as at the end of a run, links every keyframe to the nearest
 * older one that now lies within its radius and passes its scan match and gate, so where the
 * piece has already driven over the map's ground it is tied there by many links at once, not
 * by the one join link until the loop closer finds the others (ACES split, six starts of the
 * second session: the relation error over both sessions lower in five, by 0.00013 m on
 * average). The loop closer's copy of the graph takes the moved poses and the new links with
 * its next job, and from then on its searches reach the old map through them. A piece never
 * joined stays in its own frame: finish() optimises each part with its own first node held
 * fixed, and the revisit sweep links no pair across the two.
 */
#include <lrgc/map_builder/CMetricMapBuilderLRGC.h>

#include <lrgc/common/se2.h>
#include <lrgc/local_registration/LocalRegistration.h>
#include <lrgc/local_registration/MotionPredictor.h>
#include <lrgc/local_registration/SweepEstimator.h>
#include <lrgc/loop_closing/LoopClosing.h>
#include <lrgc/loop_closing/RevisitLinker.h>
#include <lrgc/map_builder/KeyframeReuse.h>

namespace lrgc
{
using mrpt::math::TPose2D;

namespace
{
/** The re-matching of a map just joined: the revisit sweep over the whole graph (no split:
 * one frame now), links only (the loop closer's next solve and the final one use them).
 * Returns the links added; none where `[RevisitLinker] enabled` is off. */
size_t rematchJoinedMap(const TLRGCParams& p, const CStopToken& stop, CPoseGraph& graph,
						const TKeyframes& keyframes)
{
	if (!p.revisits.enabled) return 0;
	CRevisitLinker linker(p.revisits, p.matcher, p.loop.link_noise);
	linker.setStopToken(stop);
	return linker.linkRevisits(graph, keyframes);
}
}  // namespace

void CMetricMapBuilderLRGC::startPiece()
{
	const auto lock = lockMap();
	ASSERTMSG_(m_graph.numNodes() > 0, "startPiece() needs a map beside which to start");
	ASSERTMSG_(!m_pieceFirst, "startPiece(): a piece is already being mapped");
	m_predictor = std::make_unique<CMotionPredictor>(m_params.motion);  // a new log
	m_sweep->startNewLog();  // same laser: the estimate stays, the recent scans go
	const size_t first = m_graph.numNodes();
	m_local->setWindowStart(first, true);  // its first keyframe fixes the piece's frame
	m_reuse->setFirstCandidate(first);
	m_pieceFirst = first;
	m_pieceStartPending = true;
	m_nextScanPrior.reset();
	m_motionSinceKeyframe = TPose2D(0, 0, 0);
	m_anchorOffset = TPose2D(0, 0, 0);
	m_odometryTrustedSinceKeyframe = true;
}

void CMetricMapBuilderLRGC::freezeMap()
{
	const auto lock = lockMap();
	m_frozenNodes = m_graph.numNodes();
	if (m_loops) m_loops->setFrozenNodes(m_frozenNodes);
}

std::string CMetricMapBuilderLRGC::pieceJoinProblem(size_t node, const TPose2D& nodeInMap,
													const Eigen::Matrix3d& cov) const
{
	const auto lock = lockMap();
	ASSERTMSG_(m_pieceFirst, "pieceJoinProblem(): no piece is being mapped apart");
	const TMapLink j = linkToMap(node, nodeInMap, cov, *m_pieceFirst);
	return j.mapAround ? j.problem : std::string();
}

TPose2D CMetricMapBuilderLRGC::joinPiece(size_t node, const TPose2D& nodeInMap,
										 const Eigen::Matrix3d& cov)
{
	const auto lock = lockMap();
	ASSERTMSG_(m_pieceFirst, "joinPiece(): no piece is being mapped apart");
	const size_t first = *m_pieceFirst, n = m_graph.numNodes();
	ASSERTMSG_(node >= first && node < n, "joinPiece(): the node is not one of the piece's");
	ASSERTMSG_(cov.allFinite(), "joinPiece(): the covariance is not finite");
	// Results computed on the worker's copy in the piece's frame land before the move.
	if (m_loops) recordLoopUpdate(m_loops->drain(m_graph, anchor(), m_lastScanInMap));
	const TPose2D nodeInPiece = m_graph.pose(node);
	const TMapLink j = linkToMap(node, nodeInMap, cov, first);
	if (!j.problem.empty())
		warn(mrpt::format(
			"piece joined at (%.2f, %.2f, %.1f deg): %s; linked by the global "
			"correlation alone",
			nodeInMap.x, nodeInMap.y, mrpt::RAD2DEG(nodeInMap.phi), j.problem.c_str()));
	const TPose2D pieceInMap = compose(j.nodeInMap, inverse(nodeInPiece));
	for (size_t i = first; i < n; ++i) m_graph.setPose(i, compose(pieceInMap, m_graph.pose(i)));
	m_lastScanInMap = compose(pieceInMap, m_lastScanInMap);
	m_lastScanCov = rotateCovariance(m_lastScanCov.get(), pieceInMap.phi);
	m_lastScanSmoothingCov = rotateCovariance(m_lastScanSmoothingCov.get(), pieceInMap.phi);
	m_graph.addLink(j.link);
	m_reuse->noteLoopLink(n - 1);
	m_reuse->setFirstCandidate(0);
	++m_stats.loopClosureLinks;
	const size_t rematched = rematchJoinedMap(m_params, m_stop, m_graph, m_keyframes);
	m_stats.loopClosureLinks += rematched;  // stats.json: loop_links' rematch_or_reuse
	m_pieceFirst.reset();
	m_local->invalidate();
	m_metricMapDirty = true;
	MRPT_LOG_INFO_FMT(
		"piece of keyframes %zu..%zu joined to the map at keyframe %zu, linked "
		"to map keyframe %zu, %zu revisit links re-matched",
		first, n - 1, node, j.link.from, rematched);
	return pieceInMap;
}

}  // namespace lrgc
