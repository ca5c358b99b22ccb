/* CLoopCloser (see LoopCloser.h), steps 1-2 of the paper's loop closing for the newest
 * keyframe: the gate and the correlation through its filters; step 3, the loop link's scan
 * match and the re-matches after a closure (paper 2.2), is in LoopCloser_match.cpp, step 4 in
 * LoopCloser_close.cpp. */
#include <lrgc/loop_closing/LoopCloser.h>

#include <lrgc/scan_matching/ReferenceCloud.h>
#include <lrgc/loop_closing/UncertaintyPropagation.h>
#include <lrgc/common/CpuTime.h>
#include <lrgc/common/params_io.h>
#include <lrgc/common/se2.h>

#include <mrpt/config/CConfigFileBase.h>

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

namespace lrgc
{
using mrpt::math::TPose2D;

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
	// The near search starts with the sigma's patch (correlateGrownOnAmbiguity grows it);
	// the far search takes the patch as grown so far.
	TSearchWindow window = searchWindow(graph, *candidates, 0, true);
	TSearchWindow farWindow = searchWindow(graph, *candidates, m_ambiguityGrowth, true);
	const bool capped = windowCapped(*candidates);
	if (attemptDue(window))
		if (auto lc = searchNear(graph, scans, *candidates, window))
		{
			m_ambiguityGrowth = 0;
			collectFarStep();
			if (!m_farHeld.empty()) dropFarHeld(m_stats.farUnconfirmed);
			if (m_far) ++m_stats.farSearchesClosedOut, m_far.reset();  // the old map moved
			return lc;
		}
	if (!capped || stopped()) return std::nullopt;
	return searchBeyond(graph, scans, *candidates, farWindow);
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
	const auto corr = correlateGrownOnAmbiguity(graph, scans, c, w);
	if (!corr || stopped()) return std::nullopt;
	auto match = matchLoopLink(graph, scans, c, seedOnRidge(*corr, w, graph), w.check);
	if (!match || stopped()) return std::nullopt;
	if (!corr->ridgeAxis.isZero()) carryRidge(graph, c, *corr, *match);
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
	CCpuTimer patchTimer(m_stats.correlateCpuSeconds);
	const TPatchAndMap pm = patchAndOldMap(graph, scans, c, w);
	patchTimer.stop();
	return correlatePrepared(graph, scans, w, pm);
}

std::optional<TCorrelationResult> CLoopCloser::correlatePrepared(const CPoseGraph& graph,
																 const TScanRefs& scans,
																 const TSearchWindow& w,
																 const TPatchAndMap& pm)
{
	CCpuTimer correlateTimer(m_stats.correlateCpuSeconds);
	m_lastVerdict = TCorrelationVerdict{};  // none: an empty old map runs no correlation
	m_lastPatchCells = 0;
	if (pm.oldMap.empty()) return std::nullopt;
	++m_stats.attempts;
	++work().correlations;
	progress();
	// A noisy laser's peaks are as wide as its noise (CPatchCorrelator::setScanNoise).
	const double noise = scans[graph.numNodes() - 1]->rangeNoiseStd;
	for (CPatchCorrelator* correlatorUsed :
		 {&m_correlator, &m_farCorrelator, &m_farCheckCorrelator})
		correlatorUsed->setScanNoise(noise);
	// [LoopCloser] corridor_ridges: the near search's link carries a corridor's slide
	// (carryRidge); the far search keeps the paper's filter 2 (its places are confirmed by a
	// later, disjoint patch instead).
	m_correlator.setStraightRidges(m_params.corridor_ridges);
	const CPatchCorrelator& correlator = correlatorFor(w);
	const CCorrelationGrid grid =
		correlator.makeGrid(pm.oldMap, 3 * correlator.params().blur_sigma_m);
	const TPose2D centre = w.centre.value_or(graph.pose(graph.numNodes() - 1));
	std::optional<TCorrelationResult> corr;
	countedSearch(
		[&](TCorrelationEffort& effort)
		{
			corr = correlator.correlate(grid, pm.patch, centre, w.xy, w.theta, &effort);
			m_lastPatchCells = effort.patchCells;
		});
	const TCorrelationVerdict verdict =
		corr ? corr->checkFilters(correlator.params())
			 : TCorrelationVerdict{TCorrelationVerdict::Reason::LowScore, 0,
								   correlator.params().min_score};
	correlateTimer.stop();
	progress();
	m_lastVerdict = verdict;
	if (verdict.accepted()) return corr;
	++m_stats.rejectedByFilters;
	m_lastRejection = verdict.message();
	return std::nullopt;
}

// Step 2 with the growth for ambiguity ([LoopCloser] patch_keyframes_per_ambiguity; paper
// 2.4: a patch that is not distinctive within its window may be in a larger one). The sigma's
// patch is correlated first; rejected as ambiguous, it counts towards the growth and the
// grown patch (the sigma's plus the growth since the last closure, at most
// old_map_exclusion_keyframes) is correlated at once, its result taken if it passes the
// filters. patch_max_travel_m does not cap it: that cap keeps attempt_stride's wait short on
// sparse scans, and the grown patch adds no wait. Where the sigma's patch closes, the grown
// one is never tried: it may span a stretch the old map holds worse (a slipping corridor,
// rooms laid with drift). Nor is it tried when it adds too few cells to the sigma's patch
// (patch_grown_min_new_cells): where keyframes lie a metre or more apart, the keyframes
// added lie beyond patch_max_range_m, and the second try would be the first again, as dear.
std::optional<TCorrelationResult> CLoopCloser::correlateGrownOnAmbiguity(
	const CPoseGraph& graph, const TScanRefs& scans, const TCandidates& c, TSearchWindow& w)
{
	auto corr = correlatePatch(graph, scans, c, w);
	const bool near = !w.far && !w.check;
	if (corr || stopped() || !near) return corr;
	const TCorrelationVerdict first = m_lastVerdict;
	const size_t firstCells = m_lastPatchCells;
	m_ambiguityGrowth = grownAfter(m_params, m_ambiguityGrowth, first, near);
	TSearchWindow grown = searchWindow(graph, c, m_ambiguityGrowth, false);
	if (!retriesGrown(m_params, first, near, w.patchSize, grown.patchSize)) return corr;
	CCpuTimer patchTimer(m_stats.correlateCpuSeconds);
	const TPatchAndMap pm = patchAndOldMap(graph, scans, c, grown);
	const size_t grownCells = m_correlator.patchCells(pm.patch);
	patchTimer.stop();
	if (!grownAddsCells(m_params, firstCells, grownCells))
	{
		++m_stats.grownSkipped;
		return corr;
	}
	++m_stats.grownRetries;
	corr = correlatePrepared(graph, scans, grown, pm);
	if (corr) w = grown;
	return corr;
}

}  // namespace lrgc
