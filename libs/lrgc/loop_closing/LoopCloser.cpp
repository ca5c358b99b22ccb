#include <lrgc/loop_closing/LoopCloser.h>

#include <lrgc/scan_matching/ReferenceCloud.h>
#include <lrgc/loop_closing/UncertaintyPropagation.h>
#include <lrgc/common/CpuTime.h>
#include <lrgc/common/params_io.h>
#include <lrgc/common/se2.h>

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/math/wrap2pi.h>

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

namespace lrgc
{
using mrpt::math::TPose2D;

namespace
{
/** Re-matching after a closure takes every this many patch keyframes: neighbours 0.3 m apart
 * see the same walls, so every second one adds nearly all the information at half the cost. */
constexpr size_t kRematchStride = 2;

/** Two held loop matches agree when the pose of the newer new node they imply differs by at
 * most kAgreeXY [m] plus kAgreePerMetre of the path between the new nodes, and kAgreeTheta
 * [rad]: scan-matched loop links are good to centimetres, local chains to ~1 %. */
constexpr double kAgreeXY = 0.3, kAgreePerMetre = 0.02, kAgreeTheta = 2.0 * M_PI / 180;

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

void CLoopCloser::setStopToken(const CStopToken& stop)
{
	m_stop = stop;
	m_correlator.setStopToken(stop);
	m_farCorrelator.setStopToken(stop);
	m_farCheckCorrelator.setStopToken(stop);
	m_matcher.setStopToken(stop);
	m_optimizer.setStopToken(stop);
}

bool CLoopCloser::stopped()
{
	if (!m_stop.stopRequested()) return false;
	m_lastRejection = "stopped";
	return true;
}

// Step 1: old poses that could overlap the newest one, by Mahalanobis distance of their
// position relative to it, the offset first shortened by the overlap radius:
//   t' = t (1 - r / |t|)_+ ,  d^2 = t'^T C_xy^-1 t'  <=  gate_sigma^2.
auto CLoopCloser::gate(const CPoseGraph& graph, size_t newest) -> std::optional<TCandidates>
{
	if (newest < m_params.old_map_exclusion_keyframes) return std::nullopt;
	const size_t lastOld = newest - m_params.old_map_exclusion_keyframes;
	// The whole graph: a search cut at the uncertainty the window can cover (10 m std) never
	// reached the start of Killian's big loop (1.1 m away in truth, 10+ m std by the
	// single-path propagation), so the gate had no candidates and no correlation was tried.
	TCandidates c;
	for (const auto& r : relativeUncertainty(graph, newest))
	{
		if (r.node > lastOld) continue;
		c.allOld.push_back(r);
		const Eigen::Vector2d t(r.nodeInSource.x, r.nodeInSource.y);
		const double norm = t.norm();
		const Eigen::Vector2d ts =
			norm > m_params.overlap_radius_m
				? Eigen::Vector2d(t * (1 - m_params.overlap_radius_m / norm))
				: Eigen::Vector2d::Zero();
		const Eigen::Matrix2d Cxy =
			r.cov.topLeftCorner<2, 2>() + 1e-6 * Eigen::Matrix2d::Identity();
		if (ts.dot(Cxy.ldlt().solve(ts)) > m_params.gate_sigma * m_params.gate_sigma) continue;
		c.nodes.push_back(r.node);
		c.relative.push_back(r);
		c.sigmaXY = std::max(c.sigmaXY, std::sqrt(std::max(Cxy(0, 0), Cxy(1, 1))));
		c.sigmaTheta = std::max(c.sigmaTheta, std::sqrt(r.cov(2, 2)));
	}
	if (c.nodes.empty()) return std::nullopt;
	return c;
}

// The paper's loop closing for the newest keyframe, as a list of steps: gate, size the search,
// search (correlate the patch with the old map, match the loop link, close the loop); then,
// if the window was capped and found nothing, search beyond it.
std::optional<TLoopClosure> CLoopCloser::process(CPoseGraph& graph, const TScanRefs& scans)
{
	m_lastRejection.clear();
	m_farDue.reset();
	if (!checkDue() || stopped()) return std::nullopt;
	const size_t newest = graph.numNodes() - 1;
	const auto candidates = timedGate(graph, newest);
	if (!candidates || stopped()) return std::nullopt;
	TSearchWindow window = searchWindow(graph, *candidates);
	const bool capped = windowCapped(*candidates);
	if (attemptDue(window))
		if (auto lc = searchNear(graph, scans, *candidates, window))
		{
			collectFarStep();
			if (!m_farHeld.empty()) dropFarHeld(m_stats.farUnconfirmed);
			m_far.reset();  // the old map has moved
			return lc;
		}
	if (!capped || stopped()) return std::nullopt;
	return searchBeyond(graph, scans, *candidates, window);
}

// Steps 2-4 in the window.
std::optional<TLoopClosure> CLoopCloser::searchNear(CPoseGraph& graph, const TScanRefs& scans,
													const TCandidates& c, TSearchWindow& w)
{
	const auto t0 = std::chrono::steady_clock::now();
	const auto match = correlateAndMatch(graph, scans, c, w);
	if (!match) return std::nullopt;
	auto lc = closeLoop(graph, scans, c, w, *match);
	if (!lc) return std::nullopt;
	lc->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
	if (lc->optimized) m_stats.closureSeconds.push_back(lc->seconds);
	return lc;
}

// Every check_every keyframes (known_ground_check_every after a check that agreed with the
// map).
bool CLoopCloser::checkDue()
{
	const size_t every =
		m_onKnownGround ? m_params.known_ground_check_every : m_params.check_every;
	if (++m_keyframesSinceCheck < every) return false;
	m_keyframesSinceCheck = 0;
	m_onKnownGround = false;
	return true;
}

auto CLoopCloser::timedGate(const CPoseGraph& graph, size_t newest)
	-> std::optional<TCandidates>
{
	CCpuTimer gateTimer(m_stats.gateCpuSeconds);
	auto candidates = gate(graph, newest);
	gateTimer.stop();
	progress();
	return candidates;
}

// Steps 2-3: the correlation's pose, through its filters, refined by the scan match; the
// match carries the correlation's score and ambiguity.
auto CLoopCloser::correlateAndMatch(const CPoseGraph& graph, const TScanRefs& scans,
									const TCandidates& c, TSearchWindow& w)
	-> std::optional<TLoopMatch>
{
	const auto corr = correlatePatch(graph, scans, c, w);
	if (!corr || stopped()) return std::nullopt;
	auto match = matchLoopLink(graph, scans, c, corr->patchInMap);
	if (!match || stopped()) return std::nullopt;
	match->score = corr->score;
	match->ambiguity = corr->ambiguity;
	return match;
}

// Step 2: the patch (in the newest keyframe's frame) against the old map (map frame), through
// the paper's three filters (score, ambiguity, variance).
std::optional<TCorrelationResult> CLoopCloser::correlatePatch(const CPoseGraph& graph,
															  const TScanRefs& scans,
															  const TCandidates& c,
															  TSearchWindow& w)
{
	CCpuTimer correlateTimer(m_stats.correlateCpuSeconds);
	const TPatchAndMap pm = patchAndOldMap(graph, scans, c, w);
	if (pm.oldMap.empty()) return std::nullopt;
	++m_stats.attempts;
	++work().correlations;
	progress();
	// A noisy laser's peaks are as wide as its noise (CPatchCorrelator::setScanNoise).
	const double noise = scans[graph.numNodes() - 1]->rangeNoiseStd;
	for (CPatchCorrelator* correlatorUsed :
		 {&m_correlator, &m_farCorrelator, &m_farCheckCorrelator})
		correlatorUsed->setScanNoise(noise);
	const CPatchCorrelator& correlator = correlatorFor(w);
	const CCorrelationGrid grid =
		correlator.makeGrid(pm.oldMap, 3 * correlator.params().blur_sigma_m);
	const TPose2D centre = w.centre.value_or(graph.pose(graph.numNodes() - 1));
	std::optional<TCorrelationResult> corr;
	countedSearch(
		[&](TCorrelationEffort& effort)
		{ corr = correlator.correlate(grid, pm.patch, centre, w.xy, w.theta, &effort); });
	const TCorrelationVerdict verdict =
		corr ? corr->checkFilters(correlator.params())
			 : TCorrelationVerdict{TCorrelationVerdict::Reason::LowScore, 0,
								   correlator.params().min_score};
	correlateTimer.stop();
	progress();
	if (verdict.accepted()) return corr;
	++m_stats.rejectedByFilters;
	m_lastRejection = verdict.message();
	return std::nullopt;
}

// Step 3: the correlation's pose seeds a scan match of the newest keyframe against the old
// scans near the nearest candidate j; the result is the loop link j -> newest, vetted when
// the gate's covariance agrees with it (the back-end's bound, 3 Phi, before its own test).
auto CLoopCloser::matchLoopLink(const CPoseGraph& graph, const TScanRefs& scans,
								const TCandidates& c, const TPose2D& corrected)
	-> std::optional<TLoopMatch>
{
	CCpuTimer matchTimer(m_stats.matchCpuSeconds);
	const size_t newest = graph.numNodes() - 1;
	const size_t oldIndex = nearestCandidate(graph, c.nodes, corrected).first;
	const size_t oldNode = c.nodes[oldIndex];
	const TPose2D guessInOld = between(graph.pose(oldNode), corrected);
	const CReferenceCloud reference = oldScansNear(graph, scans, c, oldNode, corrected);
	++work().matches;
	progress();
	const auto match = m_matcher.match(reference, *scans[newest], guessInOld);
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

// The reference of step 3's match: the candidates within 2 overlap radii of the corrected
// pose, in old node's frame, cropped to the points the new scan can reach at the correlated
// pose (a few cm off): correspondence gate plus the widest line fit, with margin to spare.
CReferenceCloud CLoopCloser::oldScansNear(const CPoseGraph& graph, const TScanRefs& scans,
										  const TCandidates& c, size_t oldNode,
										  const TPose2D& corrected)
{
	const TPose2D oldInMap = graph.pose(oldNode);
	std::vector<TScan2D> refScans;
	std::vector<TPose2D> refInOld;
	for (const size_t j : c.nodes)
	{
		if (translationNorm(between(graph.pose(j), corrected)) > 2 * m_params.overlap_radius_m)
			continue;
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
		lc.rematchLinks = rematch(graph, scans, c, w.patchFirst, lc.newNode);
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

// Paper 2.2: after the loop is closed, rerun with new scan matches between the newly linked
// poses. Each patch keyframe is matched against its nearest old candidate, now that the
// poses are topologically correct.
size_t CLoopCloser::rematch(CPoseGraph& graph, const TScanRefs& scans, const TCandidates& c,
							size_t patchFirst, size_t newest)
{
	size_t added = 0;
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
		// them (chi2 of e = v(Z^-1 (+) (X_nearest^-1 (+) X_k)) above 3 Phi, DCS's bound)
		// converged to another wall, and would add a wrong link of its own.
		const Eigen::Matrix3d info = linkInformation(
			m->cov, denoisedLoopLinkNoise(m_params.link_noise, scans[k]->rangeNoiseStd));
		const Eigen::Vector3d e =
			linkResidual(graph.pose(nearest), graph.pose(k), m->scanInRef);
		if (e.dot(info * e) > 3 * m_optimizer.params().dcs_phi)
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
