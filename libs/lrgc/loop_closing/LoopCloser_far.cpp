/* CLoopCloser beyond the capped window (issue 28; see LoopCloser.h): a far search over the
 * old map within 3 sigma of the gate proposes the k best distinct places per ring of
 * far_window_xy_m (coarse grid, every heading, the newest keyframe within kFarPathRadius of
 * the old path, one best-first pass of branch and bound per ring);
 * each is checked by the full-resolution search with the paper's three filters in a small
 * window around it and by the scan match; those that pass are held until a later, disjoint
 * patch confirms exactly one of them. Trade-off: the search for places costs about one
 * correlation over the old path's extent on a grid far_resolution_m / resolution_m times
 * coarser in x, y and heading (the patch is cut at patch_max_range_m, so not more for a
 * long-range laser), the checks k small full-resolution correlations; it runs on a lane of its
 * own (LoopCloser_lane.cpp), and a loop is closed one patch later than a near one. */
#include <lrgc/common/se2.h>
#include <mrpt/math/wrap2pi.h>
#include <lrgc/loop_closing/LoopCloser.h>

#include <lrgc/common/CpuTime.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace lrgc
{
using mrpt::math::TPose2D;

namespace
{
/** Half-window of the full-resolution search around a far peak or a held place's implied pose
 * [m, rad]: the far grid's cells (0.4 m, about 2 deg of heading) and a patch's drift fit
 * inside; a look-alike elsewhere in the building does not. 2 m / 10 deg cost twice as much
 * (the check's headings x patch cells dominate its cost) and closed the hall loop alike. */
constexpr double kFarCheckXY = 1.0, kFarCheckTheta = 5.0 * M_PI / 180;
/** The check's ambiguity filter (the best pose against the best one outside its cluster in
 * that window): a true place in a corridor has a slid copy of itself within a few metres
 * (1.14-1.20 within 2 m on the hall loop); the later patch's confirmation tells places
 * apart. */
constexpr double kFarCheckAmbiguity = 1.1;
/** Far peaks proposed must score at least this share of the best one: a true place scores
 * about as well as the best look-alike, a junk peak far less. */
constexpr double kFarPeakShare = 0.8;
/** Checks by later, disjoint patches a held place gets before it is dropped: a true place in a
 * corridor fails the check's filters at some of them (3 dropped the hall loop's true place). */
constexpr size_t kFarConfirmTries = 10;
/** A revisit stands about where the robot stood before: the far search puts the newest
 * keyframe within this distance [m] of an old keyframe only (a corridor's width, with margin
 * for a hall crossed a little apart). */
constexpr double kFarPathRadius = 3.0;
/** The far search runs only while window_sigmas sigma exceeds the window's cap this many
 * times. Intel, ACES and MIT-CSAIL stay below; Killian's gate reaches 24 caps (the hall
 * loop's 9 at its return), so no such threshold keeps the far search off Killian. */
constexpr double kFarBeyondCap = 4.0;
}  // namespace

// The far search's correlator: the same operator on a coarser grid (far_resolution_m), its
// blur at least a cell; its clusters as wide as the full-resolution check's window, so that no
// two peaks fall in one such window.
TPatchCorrelatorParams CLoopCloser::farCorrelatorParams(const TPatchCorrelatorParams& near,
														const TLoopCloserParams& p)
{
	TPatchCorrelatorParams far = near;
	far.resolution_m = std::max(near.resolution_m, p.far_resolution_m);
	far.blur_sigma_m = std::max(near.blur_sigma_m, far.resolution_m);
	far.cluster_radius_m = kFarCheckXY;
	far.cluster_radius_phi = kFarCheckTheta;
	return far;
}

// The check around a far peak or a held place: full resolution, the three filters, with an
// ambiguity filter of kFarCheckAmbiguity at most.
TPatchCorrelatorParams CLoopCloser::farCheckParams(const TPatchCorrelatorParams& near)
{
	TPatchCorrelatorParams check = near;
	check.min_ambiguity = std::min(near.min_ambiguity, kFarCheckAmbiguity);
	return check;
}

// The cap binds by kFarBeyondCap or more: the true place may lie well outside the window.
bool CLoopCloser::windowCapped(const TCandidates& c) const
{
	return m_params.far_search_every_keyframes > 0 &&
		   (m_params.window_sigmas * c.sigmaXY >= kFarBeyondCap * m_params.max_window_xy_m ||
			m_params.window_sigmas * c.sigmaTheta >= kFarBeyondCap * m_params.max_window_phi);
}

// The far search's half-window [m]: window_sigmas sigma of the gate's position, at least
// far_window_xy_m (patchAndOldMap cuts it at the old map's extent).
double CLoopCloser::farHalfWindow(const TCandidates& c) const
{
	return std::max(m_params.far_window_xy_m, m_params.window_sigmas * c.sigmaXY);
}

// The window was capped and found nothing. Once the far lane is free (LoopCloser_lane.cpp):
// with a held far place whose patch this one does not overlap, check the held places with it
// (it may close the loop); else a far search starts every far_search_every_keyframes such
// checks, and while one is under way its next step is due (farStep, once the job's result is
// handed over). A search still checking its places when the next is due, its rings done and
// its best place checked, is superseded (supersedeFar): the newer patch overlaps the old map
// more, and no search is ever dropped for its age.
std::optional<TLoopClosure> CLoopCloser::searchBeyond(CPoseGraph& graph, const TScanRefs& scans,
													  const TCandidates& c,
													  const TSearchWindow& w)
{
	if (!farLaneFree())
	{
		++m_stats.farSearchesWaited;
		return std::nullopt;
	}
	TCandidates all;
	all.relative = c.allOld;
	for (const auto& r : all.relative) all.nodes.push_back(r.node);
	all.sigmaXY = c.sigmaXY, all.sigmaTheta = c.sigmaTheta;
	const bool due = ++m_checksSinceFar >= m_params.far_search_every_keyframes;
	if (farHeldReady(w)) return confirmFar(graph, scans, all, w);
	if (m_far && due && m_far->ringsDone() && m_far->nextPlace > 0)
		supersedeFar(graph, farHalfWindow(all));
	if (!m_far && !due) return std::nullopt;
	if (!m_far) m_checksSinceFar = 0;
	m_farDue.emplace(std::move(all), w);
	return std::nullopt;
}

// The search under way ends for the one about to start. Its places not yet checked, carried to
// the newest keyframe n as a check would (place (+) (X_k^-1 (+) X_n)), lie in the later
// window when within laterHalfXY of X_n in x and y: that search correlates them again.
void CLoopCloser::supersedeFar(const CPoseGraph& graph, double laterHalfXY)
{
	const TFarSearch& f = *m_far;
	const TPose2D n = graph.pose(graph.numNodes() - 1);
	const TPose2D kToN = between(f.newestInMap, n);
	const bool held = std::all_of(
		f.places.begin() + std::ptrdiff_t(f.nextPlace), f.places.end(),
		[&](const TCorrelationPeak& p)
		{
			const TPose2D at = compose(p.patchInMap, kToN);
			return std::abs(at.x - n.x) <= laterHalfXY && std::abs(at.y - n.y) <= laterHalfXY;
		});
	if (held)
	{
		++m_stats.farSearchesMerged;
		m_stats.farPlacesMerged += f.places.size() - f.nextPlace;
	}
	else
	{
		m_stats.farDroppedKeyframes.push_back(f.newest);
		m_stats.farDroppedPoses.push_back(graph.pose(f.newest));
	}
	m_far.reset();
}

// One step of the far search on this (the lane's own) loop closer: its start and its search
// for places, or the check of its next place.
void CLoopCloser::runFarStep(const CPoseGraph& graph, const TScanRefs& scans,
							 const TCandidates& all, const TSearchWindow& w)
{
	CCpuTimer farTimer(m_stats.farCpuSeconds);
	m_onFarLane = true;
	if (!m_far) startFarSearch(graph, scans, all, w);
	if (!m_far || stopped()) return;
	if (m_far->nextRing < m_far->rings)
		farSearchPeaks();
	else
		checkFarPlace(graph, scans, all, w);
}

// A far search starts: the patch (newest keyframe's frame), the old map on the coarse grid
// within the window, and the old keyframes' positions; its next steps are the search for
// places, one ring of the window at a time (farSearchPeaks), and a check of each place found.
// The window's half-side is window_sigmas sigma of the gate's position, at least
// far_window_xy_m, and at most the old map's extent (patchAndOldMap cuts it there): a revisit
// stands where the drift put it, 126 m away (median) on the held-out long-range log.
void CLoopCloser::startFarSearch(const CPoseGraph& graph, const TScanRefs& scans,
								 const TCandidates& all, TSearchWindow w)
{
	CCpuTimer correlateTimer(m_stats.correlateCpuSeconds);
	w.far = true;
	w.xy = farHalfWindow(all);
	w.theta = M_PI;
	TPatchAndMap pm = patchAndOldMap(graph, scans, all, w);
	if (pm.oldMap.empty() || pm.patch.empty()) return;
	++m_stats.farSearches;
	++work().correlations;
	work().farMapPoints += pm.oldMap.size();
	progress();
	TFarSearch f;
	f.newest = graph.numNodes() - 1;
	f.newestInMap = graph.pose(f.newest);
	f.halfXY = w.xy;
	f.rings = static_cast<size_t>(std::ceil(w.xy / m_params.far_window_xy_m - 1e-9));
	f.rings = std::max<size_t>(f.rings, 1);
	m_stats.farRings += f.rings;
	f.patch = std::move(pm.patch);
	f.origins.radius = kFarPathRadius;
	for (const auto& r : all.relative)
	{
		const TPose2D p = graph.pose(r.node);
		f.origins.points.emplace_back(p.x, p.y);
	}
	f.grid = m_farCorrelator.makeGrid(pm.oldMap, 3 * m_farCorrelator.params().blur_sigma_m);
	m_far = std::move(f);
}

// The places to check in the window's next ring (ring r: the newest keyframe more than
// r far_window_xy_m and at most (r + 1) far_window_xy_m from where the map has it, in x or y;
// ring 0 is the square within far_window_xy_m): the far_candidates best distinct poses over
// every heading, each the best outside the kFarCheckXY / kFarCheckTheta clusters of those
// before it, scoring at least kFarPeakShare of the ring's best, with the newest keyframe near
// the old path (kFarPathRadius), in one best-first pass of branch and bound
// (CPatchCorrelator::correlatePeaks). Per ring, so that look-alikes in a wide window do not
// push the true place out of the list (Killian's one far closure was lost that way with a
// single list over 250 m), and one ring per step on the lane. Once every ring is searched, the
// places of all rings are ordered by their coarse score, so that the full-resolution checks go
// to the best places in any ring first (coarse to fine: the true place of the hall loop and of
// Killian scored best, 0.986 and 0.992 against 0.93-0.95 for look-alikes, but stood in the
// middle of the per-ring lists' order).
void CLoopCloser::farSearchPeaks()
{
	CCpuTimer correlateTimer(m_stats.correlateCpuSeconds);
	TFarSearch& f = *m_far;
	const double ring = m_params.far_window_xy_m;
	const size_t r = f.nextRing++;
	TOriginRegion origins = f.origins;
	origins.beyondXY = double(r) * ring;
	const double half = std::min(f.halfXY, double(r + 1) * ring);
	std::vector<TCorrelationPeak> peaks;
	countedSearch(
		[&](TCorrelationEffort& effort)
		{
			peaks = m_farCorrelator.correlatePeaks(f.grid, f.patch, f.newestInMap, half, M_PI,
												   m_params.far_candidates, kFarPeakShare, 0,
												   origins, &effort);
		});
	f.places.insert(f.places.end(), peaks.begin(), peaks.end());
	m_stats.farCandidates += peaks.size();
	if (f.ringsDone())
		std::stable_sort(f.places.begin(), f.places.end(),
						 [](const TCorrelationPeak& a, const TCorrelationPeak& b)
						 { return a.score > b.score; });
}

// The next place of the far search, checked around the pose of the newest keyframe n it
// implies, X_n' = place (+) (X_k^-1 (+) X_n) (k the search's keyframe); held if it passes
// (one per place: matches that agree are one). After the last place the search is done.
void CLoopCloser::checkFarPlace(const CPoseGraph& graph, const TScanRefs& scans,
								const TCandidates& all, const TSearchWindow& w)
{
	TFarSearch& f = *m_far;
	if (f.nextPlace < f.places.size())
	{
		const TPose2D place = f.places[f.nextPlace++].patchInMap;
		const TPose2D kToN = between(f.newestInMap, graph.pose(graph.numNodes() - 1));
		const auto m = matchAround(graph, scans, all, w, compose(place, kToN));
		if (!m)
			++m_stats.farRejected;
		else
		{
			++m_stats.farConfirmed;
			const bool known = std::any_of(
				m_farHeld.begin(), m_farHeld.end(),
				[&](const TFarHeld& h) { return matchesAgree(graph, h.match.link, m->link); });
			if (!known) m_farHeld.push_back({*m, 0}), ++m_stats.heldForConfirmation;
		}
	}
	if (f.nextPlace < f.places.size()) return;
	m_far.reset();
	if (!m_farHeld.empty())
		m_lastRejection = "far matches held until a later patch confirms one";
}

// Steps 2-3 in a small window around `centre` (map <- newest): the full-resolution search
// with the three filters, then the scan match of the loop link.
auto CLoopCloser::matchAround(const CPoseGraph& graph, const TScanRefs& scans,
							  const TCandidates& all, const TSearchWindow& w,
							  const TPose2D& centre) -> std::optional<TLoopMatch>
{
	TSearchWindow around = w;
	around.centre = centre;
	around.xy = kFarCheckXY;
	around.theta = kFarCheckTheta;
	around.check = true;
	return correlateAndMatch(graph, scans, all, around);
}

// Whether patch_min_keyframes or more of `w`'s patch come after the held place's patch (its
// link's newest keyframe and those before it): a patch as large as any near search's, and
// evidence of its own. Waiting for all of `w`'s patch (up to old_map_exclusion_keyframes, as
// large as the gate's sigma asks) to clear the held one confirmed LargeLoop's 117 m return
// 5-10 m of path too late.
bool CLoopCloser::farHeldBefore(const TFarHeld& h, const TSearchWindow& w) const
{
	const size_t newest = w.patchFirst + w.patchSize - 1;
	return newest >= h.match.link.to + m_params.patch_min_keyframes;
}

// The patch of `w` from the keyframe after the held place's newest on.
auto CLoopCloser::confirmingWindow(const TFarHeld& h, const TSearchWindow& w) -> TSearchWindow
{
	TSearchWindow c = w;
	const size_t newest = w.patchFirst + w.patchSize - 1;
	c.patchFirst = std::max(w.patchFirst, h.match.link.to + 1);
	c.patchSize = newest + 1 - c.patchFirst;
	return c;
}

bool CLoopCloser::farHeldReady(const TSearchWindow& w) const
{
	return std::any_of(m_farHeld.begin(), m_farHeld.end(),
					   [&](const TFarHeld& h) { return farHeldBefore(h, w); });
}

// A later patch, sharing no keyframe with a held place's patch, is searched for around the
// pose of the newest keyframe n each such place implies, X_n' = X_j (+) z_jk (+) (X_k^-1 (+)
// X_n); the loop is closed with both links when exactly one place is matched there and agrees.
// Places held later (their patch overlaps this one) wait for their own disjoint patch, so a
// look-alike held first does not keep the far search from the true place.
std::optional<TLoopClosure> CLoopCloser::confirmFar(CPoseGraph& graph, const TScanRefs& scans,
													const TCandidates& all,
													const TSearchWindow& w)
{
	const size_t newest = graph.numNodes() - 1;
	const auto t0 = std::chrono::steady_clock::now();
	const auto ready = [&](const TFarHeld& h) { return farHeldBefore(h, w); };
	std::vector<std::pair<size_t, TLoopMatch>> agreeing;
	onFarLane(
		[&]
		{
			for (size_t i = 0; i < m_farHeld.size() && !stopped(); ++i)
			{
				if (!ready(m_farHeld[i])) continue;
				const TLink& l = m_farHeld[i].match.link;
				const TPose2D implied = compose(compose(graph.pose(l.from), l.toInFrom),
												between(graph.pose(l.to), graph.pose(newest)));
				const TSearchWindow own = confirmingWindow(m_farHeld[i], w);
				if (auto m = matchAround(graph, scans, all, own, implied);
					m && matchesAgree(graph, l, m->link))
					agreeing.emplace_back(i, *m);
			}
		});
	if (stopped()) return std::nullopt;
	if (agreeing.size() != 1)
	{
		const bool ambiguous = agreeing.size() > 1;
		for (TFarHeld& h : m_farHeld) h.tries += ready(h) ? 1 : 0;
		dropFarHeldIf([&](const TFarHeld& h)
					  { return ready(h) && (ambiguous || h.tries >= kFarConfirmTries); },
					  ambiguous ? m_stats.farAmbiguous : m_stats.farUnconfirmed);
		return std::nullopt;
	}
	const TLoopMatch held = m_farHeld[agreeing[0].first].match;
	const TSearchWindow own = confirmingWindow(m_farHeld[agreeing[0].first], w);
	m_farHeld.erase(m_farHeld.begin() + std::ptrdiff_t(agreeing[0].first));
	dropFarHeld(m_stats.farUnconfirmed);  // the places the patch did not confirm
	if (m_far) ++m_stats.farSearchesClosedOut, m_far.reset();  // the old map is about to move
	std::vector<size_t> vettedLinks;
	const size_t heldId = graph.addLink(held.link);
	if (held.vetted) vettedLinks.push_back(heldId);
	auto lc = addAndClose(graph, scans, all, own, agreeing[0].second, heldId, vettedLinks);
	if (!lc) return std::nullopt;
	++m_stats.farClosures;
	lc->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
	if (lc->optimized) m_stats.closureSeconds.push_back(lc->seconds);
	return lc;
}

// Drops every held far place, counting them in `counter`.
void CLoopCloser::dropFarHeld(size_t& counter)
{
	dropFarHeldIf([](const TFarHeld&) { return true; }, counter);
}

// Drops the held far places `drop` selects, counting them in `counter`.
void CLoopCloser::dropFarHeldIf(const std::function<bool(const TFarHeld&)>& drop,
								size_t& counter)
{
	const auto end = std::remove_if(m_farHeld.begin(), m_farHeld.end(), drop);
	const auto n = size_t(m_farHeld.end() - end);
	counter += n;
	m_stats.unconfirmed += n;
	m_farHeld.erase(end, m_farHeld.end());
}

}  // namespace lrgc
