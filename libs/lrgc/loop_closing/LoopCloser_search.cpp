/* CLoopCloser, step 2's search (see LoopCloser.h): the window and patch size the gate's
 * uncertainty sets (paper 2.4), the patch and the old map it is correlated with, and the
 * correlation with its work counted for the worker's schedule (LoopWork.h). */
#include <lrgc/common/se2.h>
#include <lrgc/loop_closing/LoopCloser.h>

#include <algorithm>
#include <utility>
#include <vector>

namespace lrgc
{
using mrpt::math::TPose2D;

// The search window and the patch size from the uncertainty (paper 2.4): +- window_sigmas
// sigma, capped; the patch grows linearly with sigma, so a large loop is closed only on strong
// evidence, but spans at most patch_max_travel_m of the robot's path (never fewer than
// patch_min_keyframes keyframes): where keyframes lie a metre apart (sparse scans) a patch of
// 40 keyframes would be 40 m of corridor, matched once in 15 checks (`capTravel`; the grown
// patch, which adds no wait, is not capped). `ambiguityGrowth` more keyframes for the grown
// patch (correlateGrownOnAmbiguity), 0 for the sigma's.
auto CLoopCloser::searchWindow(const CPoseGraph& graph, const TCandidates& c,
							   size_t ambiguityGrowth, bool capTravel) const -> TSearchWindow
{
	const size_t newest = graph.numNodes() - 1;
	TSearchWindow w;
	w.xy = std::clamp(m_params.window_sigmas * c.sigmaXY,
					  2 * m_correlator.params().resolution_m, m_params.max_window_xy_m);
	w.theta = std::clamp(m_params.window_sigmas * c.sigmaTheta, mrpt::DEG2RAD(2.0),
						 m_params.max_window_phi);
	w.patchSize = patchKeyframes(m_params, c.sigmaXY, ambiguityGrowth);
	if (capTravel && m_params.patch_max_travel_m > 0)
		w.patchSize = std::max(
			m_params.patch_min_keyframes,
			std::min(w.patchSize, keyframesWithinTravel(graph, m_params.patch_max_travel_m)));
	w.grownByAmbiguity = std::min(w.patchSize - m_params.patch_min_keyframes, ambiguityGrowth);
	w.patchFirst = newest + 1 - std::min(w.patchSize, newest + 1);
	return w;
}

// patch_min_keyframes + patch_keyframes_per_m sigma + the growth for ambiguity, at most
// old_map_exclusion_keyframes.
size_t CLoopCloser::patchKeyframes(const TLoopCloserParams& p, double sigmaXY,
								   size_t ambiguityGrowth)
{
	return std::min<size_t>(p.old_map_exclusion_keyframes,
							p.patch_min_keyframes +
								static_cast<size_t>(p.patch_keyframes_per_m * sigmaXY) +
								ambiguityGrowth);
}

// The growth after a correlation's verdict: patch_keyframes_per_ambiguity more for a near
// search rejected as ambiguous (paper 2.4: a patch that is not distinctive within its window
// may be in a larger one), at most old_map_exclusion_keyframes; unchanged otherwise. The far
// search's correlations (its coarse grid, its checks) have windows of their own.
size_t CLoopCloser::grownAfter(const TLoopCloserParams& p, size_t growth,
							   const TCorrelationVerdict& verdict, bool nearSearch)
{
	if (!nearSearch || verdict.rejection != TCorrelationVerdict::Reason::Ambiguous)
		return growth;
	return std::min(growth + p.patch_keyframes_per_ambiguity, p.old_map_exclusion_keyframes);
}

// The grown patch is tried after an ambiguous near correlation, when it is larger than the
// one rejected (old_map_exclusion_keyframes may cap both).
bool CLoopCloser::retriesGrown(const TLoopCloserParams& p, const TCorrelationVerdict& verdict,
							   bool nearSearch, size_t sigmaPatch, size_t grownPatch)
{
	return p.patch_keyframes_per_ambiguity > 0 && nearSearch &&
		   verdict.rejection == TCorrelationVerdict::Reason::Ambiguous &&
		   grownPatch > sigmaPatch;
}

// patch_grown_min_new_cells: the grown patch's cells hold the sigma's (its keyframes are more
// of the newest, in the same frame); the rest are new.
bool CLoopCloser::grownAddsCells(const TLoopCloserParams& p, size_t sigmaCells,
								 size_t grownCells)
{
	const double added = double(grownCells) - double(sigmaCells);
	return added >= p.patch_grown_min_new_cells * double(sigmaCells);
}

// How many of the newest keyframes lie within `travel` [m] of path (the sum of the straight
// steps between consecutive keyframes, map frame) back from the newest; at least 1.
size_t CLoopCloser::keyframesWithinTravel(const CPoseGraph& graph, double travel)
{
	size_t k = graph.numNodes() - 1;
	double path = 0;
	while (k > 0)
	{
		const TPose2D a = graph.pose(k), b = graph.pose(k - 1);
		path += std::hypot(a.x - b.x, a.y - b.y);
		if (path > travel) break;
		--k;
	}
	return graph.numNodes() - k;
}

// A patch grown with the uncertainty overlaps the last attempt's almost entirely: while it is
// large, correlate only every attempt_stride * (patch - patch_min) checks. The keyframes
// added for ambiguity do not count: they make an attempt decisive, not rarer.
bool CLoopCloser::attemptDue(const TSearchWindow& w)
{
	if (double(++m_checksSinceAttempt) <=
		m_params.attempt_stride *
			double(w.patchSize - w.grownByAmbiguity - m_params.patch_min_keyframes))
		return false;
	m_checksSinceAttempt = 0;
	return true;
}

// A point of a scan (beam order) seen past a nearer edge: a beam within two of it returned
// more than `gap` [m] nearer (a railing's post, a glass pane's frame, a door's edge, or the
// same wall nearer along a grazing view).
static bool seenThroughGap(const std::vector<Eigen::Vector2d>& points, size_t i, double gap)
{
	const double r = points[i].norm() - gap;
	const size_t lo = i >= 2 ? i - 2 : 0, hi = std::min(points.size() - 1, i + 2);
	for (size_t j = lo; j <= hi; ++j)
		if (j != i && points[j].norm() < r) return true;
	return false;
}

// The patch: the points of keyframes first..newest within maxRange of the newest keyframe, in
// its frame; of an older keyframe's points, those it saw farther than maxRange away through
// a gap (seenThroughGap, farGap > 0) are left out. A keyframe 8-16 m back along the path sees
// the newest's surroundings from up to 28 m: where that view passes railings and glass, its
// returns are the far side's between posts, mixed pixels at the posts' edges and panes'
// returns, which no keyframe near the place sees alike. In the glass atrium such points (543
// of a first return's 2397 with a 1 m gap; seed 3, keyframe 992) lifted a look-alike 7.8 m
// along the south hall to 0.613 > min_score, a false closure; without them no pose reaches
// min_score there. A far surface seen face on (an end wall down a corridor) stays in; a wall
// at a grazing angle, its beams stepping away from each other, goes with the gaps (a gap
// bounded on both sides only let the false closure back: doc/generalisation.md, the atrium).
std::vector<Eigen::Vector2d> CLoopCloser::patchPoints(const CPoseGraph& graph,
													  const TScanRefs& scans, size_t first,
													  double maxRange, double farGap,
													  double& radius)
{
	const size_t newest = graph.numNodes() - 1;
	const TPose2D newestInMap = graph.pose(newest);
	std::vector<Eigen::Vector2d> patch;
	radius = 0;
	for (size_t k = first; k <= newest; ++k)
	{
		const CPointTransform kInNewest(between(newestInMap, graph.pose(k)));
		const auto& points = scans[k]->points;
		for (size_t i = 0; i < points.size(); ++i)
		{
			const Eigen::Vector2d q = kInNewest(points[i]);
			const double range = q.norm();
			if (range > maxRange) continue;
			if (farGap > 0 && points[i].norm() > maxRange && seenThroughGap(points, i, farGap))
				continue;
			patch.push_back(q);
			radius = std::max(radius, range);
		}
	}
	return patch;
}

// The patch (patchPoints). The old map: the candidates' points the patch can reach from
// inside the window [map frame]. A window wider than the old map can be (max_window_xy_m
// lifted) gains nothing: beyond the farthest old point plus the patch radius and the blur's
// reach (p(m) > 0 up to 3.53 sigma; 4 sigma and two cells of margin), no patch point meets the
// map, so w.xy shrinks to that.
auto CLoopCloser::patchAndOldMap(const CPoseGraph& graph, const TScanRefs& scans,
								 const TCandidates& c, TSearchWindow& w) const -> TPatchAndMap
{
	const TPose2D newestInMap = graph.pose(graph.numNodes() - 1);
	TPatchAndMap pm;
	double patchRadius = 0;
	pm.patch = patchPoints(graph, scans, w.patchFirst, m_params.patch_max_range_m,
						   m_params.patch_far_gap_m, patchRadius);
	const TPose2D centreInMap = w.centre.value_or(newestInMap);
	const Eigen::Vector2d centre(centreInMap.x, centreInMap.y);
	const CPatchCorrelator& correlator = correlatorFor(w);
	const double blur = correlator.params().blur_sigma_m;
	const double reach = w.xy + patchRadius + 3 * blur;
	for (const size_t j : c.nodes)
	{
		const CPointTransform toMap(graph.pose(j));
		for (const auto& p : scans[j]->points)
			if (Eigen::Vector2d q = toMap(p); (q - centre).squaredNorm() <= reach * reach)
				pm.oldMap.push_back(q);
	}
	if (pm.oldMap.empty()) return pm;
	double farthest = 0;
	for (const auto& q : pm.oldMap) farthest = std::max(farthest, (q - centre).norm());
	w.xy = std::min(w.xy,
					farthest + patchRadius + 4 * blur + 2 * correlator.params().resolution_m);
	return pm;
}

// A correlation, its work counted as the search goes (the worker's published progress):
// headings x patch cells once known, then poses scored x patch cells.
void CLoopCloser::countedSearch(const std::function<void(TCorrelationEffort&)>& search)
{
	TCorrelationEffort effort;
	double counted = 0;  // poses scored x cells counted so far
	bool prepared = false;
	effort.onProgress = [this, &counted, &prepared](const TCorrelationEffort& e)
	{
		if (!std::exchange(prepared, true))
			work().correlationAngleCells += double(e.headings) * double(e.patchCells);
		const double poseCells = double(e.posesScored) * double(e.patchCells);
		work().correlationPoseCells += poseCells - counted;
		counted = poseCells;
		progress();
	};
	search(effort);
	work().correlationPoseCells +=
		double(effort.posesScored) * double(effort.patchCells) - counted;
}

}  // namespace lrgc
