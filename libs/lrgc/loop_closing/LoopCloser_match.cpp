/* CLoopCloser (see LoopCloser.h), step 3 of the paper's loop closing and its aftermath: the
 * scan match that refines the correlation's pose into the loop link (seeded on a corridor's
 * ridge where the correlation found one, retried on the pass through the place), and the
 * re-matches after a closure (paper 2.2). Steps 1-2 are in LoopCloser.cpp, step 4 in
 * LoopCloser_close.cpp. */
#include <lrgc/loop_closing/LoopCloser.h>

#include <lrgc/scan_matching/ReferenceCloud.h>
#include <lrgc/loop_closing/UncertaintyPropagation.h>
#include <lrgc/common/CpuTime.h>
#include <lrgc/common/se2.h>
#include <mrpt/math/wrap2pi.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace lrgc
{
using mrpt::math::TPose2D;
namespace
{
/** Re-matching after a closure takes every this many patch keyframes: neighbours 0.3 m apart
 * see the same walls, so every second one adds nearly all the information at half the cost. */
constexpr size_t kRematchStride = 2;
/** Keyframes of one pass through a place lie at most this many indices apart within its
 * reference radius (a pass's keyframes are consecutive; 3 allows a few turned away). */
constexpr size_t kVisitGap = 3;

/** Index in `candidates` of the node nearest to `pose` (map frame) and its distance [m]; the
 * first on ties. */
std::pair<size_t, double> nearestCandidate(const CPoseGraph& graph,
										   const std::vector<size_t>& candidates,
										   const TPose2D& pose)
{
	size_t nearest = 0;
	double best = 1e18;
	for (size_t i = 0; i < candidates.size(); ++i)
		if (const double d = translationNorm(between(graph.pose(candidates[i]), pose));
			d < best)
			best = d, nearest = i;
	return {nearest, best};
}

/* Innovation chi2 of a loop link i -> j (Z = (i <- j), information Omega) against the gate's
 * covariance C of P = (j <- i) (propagateUncertainty from j):
 *     T = P^-1 = (i <- j),  C_T = inverseCovariance(P, C)
 *     e = v(Z^-1 (+) T),  S = A C_T A^T + Omega^-1,  A = diag(R(z_phi)^T, 1)
 *     chi2 = e^T S^-1 e   [-, 3 dof]
 * the same form as the back-end's test (PoseGraphOptimizer.cpp), with the gate's covariance in
 * place of the graph's marginal. */
double gateInnovationChi2(const TRelativeUncertainty& iFromJ, const TPose2D& z,
						  const Eigen::Matrix3d& omega)
{
	const TPose2D& P = iFromJ.nodeInSource;
	Eigen::Matrix3d A = Eigen::Matrix3d::Identity();
	const double cz = std::cos(z.phi), sz = std::sin(z.phi);
	A.topLeftCorner<2, 2>() << cz, sz, -sz, cz;
	const Eigen::Matrix3d S =
		A * inverseCovariance(P, iFromJ.cov) * A.transpose() + omega.inverse();
	const Eigen::Vector3d e = toVector(between(z, inverse(P)));
	return e.dot(S.ldlt().solve(e));
}

/** A link's information with a doubt D [map frame] added to its covariance, the link read in
 * the frame of its old node (heading theta_j [rad]):
 *     (Omega^-1 + A D A^T)^-1,  A = diag(R(theta_j)^T, 1). */
Eigen::Matrix3d withDoubt(const Eigen::Matrix3d& info, const Eigen::Matrix3d& doubt,
						  double thetaJ)
{
	if (doubt.isZero()) return info;
	Eigen::Matrix3d A = Eigen::Matrix3d::Identity();
	A.topLeftCorner<2, 2>() << std::cos(thetaJ), std::sin(thetaJ), -std::sin(thetaJ),
		std::cos(thetaJ);
	return (info.inverse() + A * doubt * A.transpose()).inverse();
}

}  // namespace

// Where the best peak is a straight ridge (TCorrelationResult::ridgeAxis: a corridor's slide,
// look-alikes along it), the correlation says little along it: the best pose there is the
// first among near-equals. The gate's prediction (the window's centre c) is the better guess
// along it, so the scan match starts from its projection onto the ridge's line, within the
// ridge's extent (b the best pose, a the axis, L the half-length; map frame):
//     t = clamp(a . (c - b), -L, L),  seed = (b + t a, theta_b).
TPose2D CLoopCloser::seedOnRidge(const TCorrelationResult& corr, const TSearchWindow& w,
								 const CPoseGraph& graph) const
{
	TPose2D seed = corr.patchInMap;
	if (corr.ridgeAxis.isZero()) return seed;
	const TPose2D centre = w.centre.value_or(graph.pose(graph.numNodes() - 1));
	const Eigen::Vector2d d(centre.x - seed.x, centre.y - seed.y);
	const double t =
		std::clamp(corr.ridgeAxis.dot(d), -corr.ridgeHalfLength, corr.ridgeHalfLength);
	seed.x += t * corr.ridgeAxis.x();
	seed.y += t * corr.ridgeAxis.y();
	return seed;
}

// The scan match seeded on a ridge keeps the ridge's doubt along it, and where it starts on
// the wrong one of two look-alike places along the ridge it converges a few centimetres off
// across it too: the correlation's own spread C_corr and the ridge's C_ridge (map frame,
// TCorrelationResult::ridgeCovariance) are rotated into the old node j's frame, the link's,
// and added to the match's:
//     C_link = C_match + A (C_corr + C_ridge) A^T,  A = diag(R(theta_j)^T, 1),
// and the link is vetted against the gate again with it.
void CLoopCloser::carryRidge(const CPoseGraph& graph, const TCandidates& c,
							 const TCorrelationResult& corr, TLoopMatch& m) const
{
	m.doubt = corr.cov + corr.ridgeCovariance();
	m.info = withDoubt(m.info, m.doubt, graph.pose(m.link.from).phi);
	m.link.information = m.info;
	const size_t index =
		size_t(std::find(c.nodes.begin(), c.nodes.end(), m.link.from) - c.nodes.begin());
	m.vetted = gateInnovationChi2(c.relative[index], m.link.toInFrom, m.info) <
			   3 * m_optimizer.params().dcs_phi;
}

// Step 3: the correlation's pose seeds a scan match of the newest keyframe against the old
// scans near the nearest candidate j; the result is the loop link j -> newest, vetted when
// the gate's covariance agrees with it (the back-end's bound, 3 Phi, before its own test).
// Refused against every pass through the place, it is matched again against the pass that
// holds j alone (visitAround), where there are several: before the loop is closed the passes
// lie in the map with the drift between them, and one pass's see-through rays cross the other's
// walls. Sparse MIT-CSAIL's last place (keyframe 383 against 45, with 0-8 placed beside it):
// 97 % inliers, 2.9 cm rms, refused by free space 0.157 > 0.15 against both passes; 0.062
// against 44-46 alone, and the link agrees with the relations.
auto CLoopCloser::matchLoopLink(const CPoseGraph& graph, const TScanRefs& scans,
								const TCandidates& c, const TPose2D& corrected, bool oneVisit)
	-> std::optional<TLoopMatch>
{
	CCpuTimer matchTimer(m_stats.matchCpuSeconds);
	const size_t newest = graph.numNodes() - 1;
	const size_t oldIndex = nearestCandidate(graph, c.nodes, corrected).first;
	const size_t oldNode = c.nodes[oldIndex];
	const TPose2D guessInOld = between(graph.pose(oldNode), corrected);
	const std::vector<std::vector<size_t>> references =
		loopMatchReferences(oldNodesNear(graph, c, corrected), oldNode, oneVisit, kVisitGap);
	auto matchAgainst = [&](const std::vector<size_t>& nodes)
	{
		const CReferenceCloud reference = oldScansNear(graph, scans, oldNode, nodes, corrected);
		++work().matches;
		progress();
		return m_matcher.match(reference, *scans[newest], guessInOld);
	};
	std::optional<TScanMatch> match = matchAgainst(references.front());
	// Refused against several passes: the pass through oldNode alone.
	if (!match && references.size() > 1)
	{
		++m_stats.onePassRetries;
		match = matchAgainst(references.back());
		if (match) ++m_stats.onePassMatched;
	}
	if (!match)
	{
		++m_stats.rejectedByMatch;
		m_lastRejection = "correlation accepted but the scan match failed";
		return std::nullopt;
	}
	matchTimer.stop();
	TLoopMatch m;
	m.info = linkInformation(
		match->cov, denoisedLoopLinkNoise(m_params.link_noise, scans[newest]->rangeNoiseStd));
	m.link = {oldNode, newest, match->scanInRef, m.info, LinkType::LoopClosure};
	m.vetted = gateInnovationChi2(c.relative[oldIndex], match->scanInRef, m.info) <
			   3 * m_optimizer.params().dcs_phi;
	return m;
}

// The candidates within 2 overlap radii of the corrected pose (map frame), in index order.
// With `oneVisit` (a far place's check: the map is tens of metres wrong there, and keyframes of
// another corridor may lie where it has the place) matchLoopLink keeps only the pass through
// the place that holds oldNode (visitAround): on LargeLoop's 117 m return a drifted side of the
// loop lay on the first corridor in the map, and its scans failed the true place's match by
// free space (0.3-0.8 of the scan) for 30 keyframes after the correlation had found it (score
// 0.995).
std::vector<size_t> CLoopCloser::oldNodesNear(const CPoseGraph& graph, const TCandidates& c,
											  const TPose2D& corrected) const
{
	std::vector<size_t> near;
	for (const size_t j : c.nodes)
		if (translationNorm(between(graph.pose(j), corrected)) <= 2 * m_params.overlap_radius_m)
			near.push_back(j);
	return near;
}

// The reference of step 3's match: the scans of `near`, in old node's frame, cropped to the
// points the new scan can reach at the correlated pose (a few cm off): correspondence gate
// plus the widest line fit, with margin to spare.
CReferenceCloud CLoopCloser::oldScansNear(const CPoseGraph& graph, const TScanRefs& scans,
										  size_t oldNode, const std::vector<size_t>& near,
										  const TPose2D& corrected)
{
	const TPose2D oldInMap = graph.pose(oldNode);
	std::vector<TScan2D> refScans;
	std::vector<TPose2D> refInOld;
	for (const size_t j : near)
	{
		refScans.push_back(*scans[j]);
		work().matchRefPoints += scans[j]->points.size();
		refInOld.push_back(between(oldInMap, graph.pose(j)));
	}
	std::vector<Eigen::Vector2d> scanInOld;
	const CPointTransform toOld(between(oldInMap, corrected));
	for (const auto& p : scans[graph.numNodes() - 1]->points) scanInOld.push_back(toOld(p));
	const double cropMargin =
		m_matcherParams.max_correspondence_dist_m + 4 * m_matcherParams.normal_radius_m + 0.2;
	TScanMatcherParams refParams = m_matcherParams;
	if (m_params.match_ref_resolution_m > 0)
		refParams.ref_resolution_m = m_params.match_ref_resolution_m;
	return CReferenceCloud::fromScansNear(refScans, refInOld, refParams, scanInOld, cropMargin);
}

// Step 3's references in the order tried: every pass near the place, then the pass through
// oldNode alone if that is a part of them (a one-pass place, or oldNode outside `near`, has
// one).
std::vector<std::vector<size_t>> CLoopCloser::loopMatchReferences(std::vector<size_t> near,
																  size_t oldNode, bool oneVisit,
																  size_t maxGap)
{
	std::vector<size_t> visit = visitAround(near, oldNode, maxGap);
	if (oneVisit) return {std::move(visit)};
	if (visit.empty() || visit.size() == near.size()) return {std::move(near)};
	return {std::move(near), std::move(visit)};
}

// The visit of `nodes` (visitsOf, PoseGraph.h) that holds `node`; none if it is not among them.
std::vector<size_t> CLoopCloser::visitAround(std::vector<size_t> nodes, size_t node,
											 size_t maxGap)
{
	for (std::vector<size_t>& visit : visitsOf(std::move(nodes), maxGap))
		if (std::binary_search(visit.begin(), visit.end(), node)) return std::move(visit);
	return {};
}

// The chi2 of a re-match Z (node j in node i's frame, information Omega) against the solve's
// X_i^-1 (+) X_j, read both ways and the larger kept. The back end's residual
// e_Z = v(Z^-1 (+) X_i^-1 (+) X_j) puts the translation in Z's own axes and is read with Omega;
// the matcher's covariance is over (x, y, phi) in i's axes (doc/back-end.md), where the
// disagreement is
//     e_i = (R_i^T (t_j - t_i) - t_z, wrap(phi_j - phi_i - phi_z))   [m, m, rad],
// read with Omega^-1 + Q, Q = diag(s^2, s^2, s_phi^2) the solve's own error between the two
// (rematch_solve_std_m / _deg: it placed them from a closure a moment ago; true re-matches on
// dense Killian find it 0.11-0.13 m / 0.4-0.9 deg off). The two readings agree for a link that
// barely turns. For keyframes facing opposite ways (a corridor walked back, a turn met from
// both sides) R_z^T is close to -I: x and y read right, but the coupling of translation and
// heading flips its sign. A loose match of such a pair (few common walls: dense Killian's
// 1608 -> 3693, sd 0.98 m along x and 9.3 deg, coupled) that lands 1.36 m / 8.8 deg from the
// solve scored 6.3 in Z's axes, under 3 Phi, and was kept as a false link (1.34 m / 8 deg by
// the relations); in i's axes, where its covariance says which slide goes with which turn, it
// is far outside. A link kept must agree as its covariance means it and as the back end weighs
// it.
double CLoopCloser::rematchDisagreementChi2(const TPose2D& xi, const TPose2D& xj,
											const TPose2D& z, const Eigen::Matrix3d& info,
											const Eigen::Matrix3d& solveCov)
{
	const Eigen::Vector3d eZ = linkResidual(xi, xj, z);
	const TPose2D d = between(xi, xj);
	const Eigen::Vector3d eI(d.x - z.x, d.y - z.y, mrpt::math::wrapToPi(d.phi - z.phi));
	const Eigen::Matrix3d S = info.inverse() + solveCov;
	return std::max(eZ.dot(info * eZ), eI.dot(S.ldlt().solve(eI)));
}

// Paper 2.2: after the loop is closed, rerun with new scan matches between the newly linked
// poses. Each patch keyframe is matched against its nearest old candidate, now that the
// poses are topologically correct. A closure seeded on a ridge (`doubt`, carryRidge) placed
// them only across it: each re-match starts from that placement and keeps its doubt (tight
// re-matches along a corridor slid by the closure locked the slide in: the atrium's seed 3
// with the default gate, 12 links 0.4-0.5 m along the hall).
size_t CLoopCloser::rematch(CPoseGraph& graph, const TScanRefs& scans, const TCandidates& c,
							size_t patchFirst, size_t newest, const Eigen::Matrix3d& doubt)
{
	size_t added = 0;
	const double sXY = m_params.rematch_solve_std_m, sPhi = m_params.rematch_solve_std;
	const Eigen::Matrix3d solveCov =
		Eigen::Vector3d(sXY * sXY, sXY * sXY, sPhi * sPhi).asDiagonal();
	for (size_t k = patchFirst; k < newest && !m_stop.stopRequested(); k += kRematchStride)
	{
		const auto [index, distance] = nearestCandidate(graph, c.nodes, graph.pose(k));
		if (distance > m_params.overlap_radius_m) continue;
		const size_t nearest = c.nodes[index];
		const TPose2D guess = between(graph.pose(nearest), graph.pose(k));
		const auto m = m_matcher.match(
			CReferenceCloud::fromScan(*scans[nearest], m_matcherParams), *scans[k], guess);
		if (!m) continue;
		// The closure's solve has just placed both poses: a re-match that lands far from
		// them (chi2 above 3 Phi, DCS's bound, read in both axes: rematchDisagreementChi2)
		// converged to another wall, and would add a wrong link of its own.
		const Eigen::Matrix3d info = withDoubt(
			linkInformation(
				m->cov, denoisedLoopLinkNoise(m_params.link_noise, scans[k]->rangeNoiseStd)),
			doubt, graph.pose(nearest).phi);
		if (rematchDisagreementChi2(graph.pose(nearest), graph.pose(k), m->scanInRef, info,
									solveCov) > 3 * m_optimizer.params().dcs_phi)
		{
			++m_stats.rematchesRefused;
			continue;
		}
		graph.addLink({nearest, k, m->scanInRef, info, LinkType::LoopClosure});
		++added;
	}
	return added;
}

}  // namespace lrgc
