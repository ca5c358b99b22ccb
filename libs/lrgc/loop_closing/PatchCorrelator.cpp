/* Global correlation (Gutmann & Konolige 2000, section 2.3): patch preparation, the pose
 * grid, the best pose and its rival, the best cluster's covariance, and the three filters.
 * The searches themselves are in correlation_search.cpp, step 4's rival search and its ridge
 * rules in rival_search.cpp.
 *
 * Steps of one query:
 *  1. Reduce the patch to its distinct cells (resolution in the patch frame, centroid of the
 *     points of each), so the score is the paper's sum over cells, not over raw points
 *     (overlapping scans would otherwise weight walls by how often they were seen).
 *  2. Pose grid: dtheta = resolution / max_k |p_k| unless given; base cells per angle.
 *  3. Best pose: searched with floor = min_score (nothing below it could pass filter 1).
 *  4. Rival: the same search with the best cluster excluded, floor = S_best / min_ambiguity
 *     for branch and bound (a weaker rival cannot fail filter 2: ambiguity reported inf),
 *     stopping at the first pose that reaches the floor (its existence alone fails filter 2;
 *     the strongest rival is not needed), floor 0 and the exact rival for the exhaustive
 *     reference. A rival on the best peak's ridge (TRidgeRule: a corridor's slide) joins the
 *     best's cluster and the search goes on; a straight ridge's extent is reported with the
 *     result, filter 3 then judges the spread across it.
 *  5. Covariance (pose_grid.cpp): the response is sampled on a lattice around the best pose,
 * weighted w = exp(-(S_best - S) / (cluster_score_scale S_best)), and its weighted covariance
 * is taken, plus the lattice's own discretisation (step^2/12). First lattice: the pose grid
 * itself, +-4 steps on each axis. If the response is not contained in it, a coarser one over
 * +-3 maxStd (at most 4 samples per side). A response flat over that lattice gives std ~ 3
 * maxStd / sqrt(3) > maxStd, so filter 3 still rejects it although the lattice truncates it.
 */
#include <lrgc/loop_closing/PatchCorrelator.h>

#include <mrpt/core/bits_math.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/math/wrap2pi.h>

#include "correlation_search.h"
#include "pose_grid.h"
#include "rival_search.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace lrgc
{
namespace
{
using detail::appendBaseCells;
using detail::bestCluster;
using detail::clusterCovariance;
using detail::TGridSpec;
using detail::TPoseGridProblem;
using detail::TRidge;
using detail::TRidgeRule;

// The key of the patch cell (of `resolution`) that holds p: cx in the high 32 bits, cy's low
// 32 bits below, built on unsigned values (a left shift of a negative int64_t is undefined
// behaviour); the same bits, and the same order, as the signed expression gave.
int64_t cellKey(const Eigen::Vector2d& p, double resolution)
{
	if (!p.allFinite()) THROW_EXCEPTION("CPatchCorrelator: a patch point is not finite");
	const int64_t cx = static_cast<int64_t>(std::floor(p.x() / resolution));
	const int64_t cy = static_cast<int64_t>(std::floor(p.y() / resolution));
	const uint64_t key =
		(static_cast<uint64_t>(cx) << 32) ^ (static_cast<uint64_t>(cy) & 0xffffffffu);
	return static_cast<int64_t>(key);
}

// Step 1: centroids of the distinct cells of the patch, in a fixed pseudo-random order (so
// that early-abandoned bounds see a spatially mixed sample of points first).
std::vector<Eigen::Vector2d> distinctCells(const std::vector<Eigen::Vector2d>& pts,
										   double resolution)
{
	struct Item
	{
		int64_t key;
		Eigen::Vector2d p;
	};
	std::vector<Item> items;
	items.reserve(pts.size());
	for (const auto& p : pts) items.push_back({cellKey(p, resolution), p});
	std::sort(items.begin(), items.end(),
			  [](const Item& a, const Item& b)
			  {
				  return a.key != b.key
							 ? a.key < b.key
							 : (a.p.x() != b.p.x() ? a.p.x() < b.p.x() : a.p.y() < b.p.y());
			  });
	std::vector<Eigen::Vector2d> out;
	for (size_t k = 0; k < items.size();)
	{
		size_t e = k;
		Eigen::Vector2d sum = Eigen::Vector2d::Zero();
		for (; e < items.size() && items[e].key == items[k].key; ++e) sum += items[e].p;
		out.push_back(sum / double(e - k));
		k = e;
	}
	std::mt19937 rng(12345);
	std::shuffle(out.begin(), out.end(), rng);
	return out;
}

/** A search window run() can take: a grid, a finite centre, half widths in [0, 1000]. */
void checkWindow(const CCorrelationGrid& grid, const mrpt::math::TPose2D& center,
				 double halfWindowXY, double halfWindowTheta)
{
	if (grid.empty()) THROW_EXCEPTION("CPatchCorrelator: the old-map grid is empty");
	if (!(halfWindowXY >= 0 && halfWindowXY <= 1e3) ||
		!(halfWindowTheta >= 0 && halfWindowTheta <= 1e3) ||
		!std::isfinite(center.x + center.y + center.phi))
		THROW_EXCEPTION_FMT(
			"CPatchCorrelator: bad search window: centre (%g, %g, %g), halfWindowXY=%g m, "
			"halfWindowTheta=%g rad",
			center.x, center.y, center.phi, halfWindowXY, halfWindowTheta);
}

/* Step 2: the pose grid over the window. Headings every dtheta = angularStep, or (0) the step
 * that moves the patch's farthest cell by one cell, res / r_max, at most 0.1 rad; the whole
 * circle once when the window covers it. Positions every cell within +-halfWindowXY. The
 * patch's cells under every heading are precomputed (appendBaseCells). */
void preparePoseGrid(const CCorrelationGrid& grid, const std::vector<Eigen::Vector2d>& pts,
					 double angularStep, double halfWindowXY, double halfWindowTheta,
					 TGridSpec& spec, TPoseGridProblem& pb)
{
	double maxRadius = 0;
	for (const auto& p : pts) maxRadius = std::max(maxRadius, p.norm());
	spec.dtheta =
		angularStep > 0 ? angularStep : std::min(0.1, spec.res / std::max(maxRadius, spec.res));
	pb.grid = &grid;
	pb.numPoints = static_cast<int>(pts.size());
	pb.halfCells = static_cast<int>(std::ceil(halfWindowXY / spec.res - 1e-9));
	if (2 * halfWindowTheta + spec.dtheta >= 2 * M_PI)
	{  // the whole circle, each heading once
		pb.numAngles = static_cast<int>(std::ceil(2 * M_PI / spec.dtheta));
		spec.dtheta = 2 * M_PI / pb.numAngles;
		spec.angle0 = pb.numAngles / 2;
	}
	else
	{
		spec.angle0 = static_cast<int>(std::ceil(halfWindowTheta / spec.dtheta - 1e-9));
		pb.numAngles = 2 * spec.angle0 + 1;
	}
	pb.cellsPerAngleStep = maxRadius * spec.dtheta / spec.res;
	pb.baseCells.reserve(size_t(pb.numAngles) * pts.size() * 2);
	for (int a = 0; a < pb.numAngles; ++a)
		appendBaseCells(grid, pts, spec.center, spec.theta(a), pb.baseCells);
	pb.prepare();
}

/** The translations (i, j) of the pose grid that put the patch's origin within the region:
 * |t_c + (i, j) res - q| <= radius for some point q (any, without points), and
 * max(|i|, |j|) > ceil(beyondXY / res) when beyondXY > 0; a pyramid of as many levels as the
 * grid. */
void restrictOrigins(const TOriginRegion& origins, const TGridSpec& spec, TPoseGridProblem& pb)
{
	if (origins.points.empty() && !(origins.beyondXY > 0)) return;
	const int W = pb.halfCells, n = pb.side();
	const int inner = origins.beyondXY > 0
						  ? static_cast<int>(std::ceil(origins.beyondXY / spec.res - 1e-9))
						  : -1;
	auto allowed = [&](int i, int j) { return std::max(std::abs(i), std::abs(j)) > inner; };
	std::vector<uint8_t> level0(size_t(n) * size_t(n), 0);
	if (origins.points.empty())
		for (int i = -W; i <= W; ++i)
			for (int j = -W; j <= W; ++j)
				level0[size_t(i + W) * size_t(n) + size_t(j + W)] = allowed(i, j) ? 1 : 0;
	const double r = origins.radius / spec.res;
	const int R = static_cast<int>(std::floor(r));
	for (const Eigen::Vector2d& q : origins.points)
	{
		const double qi = (q.x() - spec.center.x) / spec.res;
		const double qj = (q.y() - spec.center.y) / spec.res;
		const int i0 = static_cast<int>(std::ceil(qi - r)),
				  j0 = static_cast<int>(std::ceil(qj - r));
		for (int i = std::max(-W, i0); i <= std::min(W, i0 + 2 * R + 1); ++i)
			for (int j = std::max(-W, j0); j <= std::min(W, j0 + 2 * R + 1); ++j)
				if ((i - qi) * (i - qi) + (j - qj) * (j - qj) <= r * r && allowed(i, j))
					level0[size_t(i + W) * size_t(n) + size_t(j + W)] = 1;
	}
	pb.setAllowed(std::move(level0), pb.grid->numLevels());
}

/** Steps 1 and 2 of a query: the patch's distinct cells and the pose grid over the window. */
struct TPreparedSearch
{
	TGridSpec spec;
	std::vector<Eigen::Vector2d> pts;
	TPoseGridProblem pb;
	int64_t full = 0;  //!< 255 N: the score of a perfect match
};

/** Prepares a query (see TPreparedSearch) and sets `effort` (never null) going: headings and
 * patch cells, then progress as the searches evaluate. False if the patch is empty. */
bool prepareSearch(const TPatchCorrelatorParams& prm, const CStopToken& stop,
				   const CCorrelationGrid& grid, const std::vector<Eigen::Vector2d>& patch,
				   const mrpt::math::TPose2D& center, double halfWindowXY,
				   double halfWindowTheta, TCorrelationEffort* effort, TPreparedSearch& s)
{
	effort->headings = effort->patchCells = effort->posesScored = 0;
	checkWindow(grid, center, halfWindowXY, halfWindowTheta);
	s.spec.center = center;
	s.spec.res = grid.resolution();
	s.pts = distinctCells(patch, s.spec.res);
	if (s.pts.empty()) return false;
	preparePoseGrid(grid, s.pts, prm.angular_step, halfWindowXY, halfWindowTheta, s.spec, s.pb);
	s.pb.stop = stop;
	s.full = int64_t(255) * s.pb.numPoints;
	effort->headings = size_t(s.pb.numAngles), effort->patchCells = s.pts.size();
	// Progress: posesScored grows by the search's steps, then takes each search's count.
	if (effort->onProgress)
	{
		effort->onProgress(*effort);
		s.pb.onEvaluations = [effort]
		{
			effort->posesScored += TPoseGridProblem::kProgressEvaluations;
			effort->onProgress(*effort);
		};
	}
	return true;
}
}  // namespace

std::string TCorrelationVerdict::message() const
{
	using R = Reason;
	switch (rejection)
	{
		case R::Accepted:
			return "accepted";
		case R::LowScore:
			return mrpt::format("score %.3f < min_score %.3f", value, limit);
		case R::Ambiguous:
			return mrpt::format("ambiguity %.3f < min_ambiguity %.3f", value, limit);
		case R::SpreadXY:
			return mrpt::format("std dev xy %.3f m > max_std_xy_m %.3f m", value, limit);
		case R::SpreadTheta:
			return mrpt::format("std dev theta %.2f deg > max_std_phi_deg %.2f deg",
								mrpt::RAD2DEG(value), mrpt::RAD2DEG(limit));
	}
	return "unknown";
}

TCorrelationVerdict TCorrelationResult::checkFilters(const TPatchCorrelatorParams& p) const
{
	using R = TCorrelationVerdict::Reason;
	// Along a straight ridge (ridgeAxis) the position is the ridge's extent, which the loop
	// link carries (ridgeCovariance); filter 3 judges the spread across it.
	const Eigen::Vector2d across(-ridgeAxis.y(), ridgeAxis.x());
	const double stdXY = ridgeAxis.isZero()
							 ? std::sqrt(std::max(cov(0, 0), cov(1, 1)))
							 : std::sqrt(across.dot(cov.topLeftCorner<2, 2>() * across));
	const double stdTh = std::sqrt(cov(2, 2));
	if (score < p.min_score) return {R::LowScore, score, p.min_score};
	if (ambiguity < p.min_ambiguity) return {R::Ambiguous, ambiguity, p.min_ambiguity};
	if (stdXY > p.max_std_xy_m) return {R::SpreadXY, stdXY, p.max_std_xy_m};
	if (stdTh > p.max_std_phi) return {R::SpreadTheta, stdTh, p.max_std_phi};
	return {};
}

Eigen::Matrix3d TCorrelationResult::ridgeCovariance() const
{
	Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
	if (ridgeAxis.isZero()) return c;
	// The true pose may lie anywhere on the ridge: its far end at 2 sigma.
	const double halfStd = ridgeHalfLength / 2;
	c.topLeftCorner<2, 2>() = halfStd * halfStd * ridgeAxis * ridgeAxis.transpose();
	c(2, 2) = std::pow(ridgeMaxDeltaTheta / 2, 2);
	return c;
}

CPatchCorrelator::CPatchCorrelator(const TPatchCorrelatorParams& params)
	: m_configured(params), m_params(params)
{
	m_params.validate();
}

void CPatchCorrelator::setScanNoise(double sigma)
{
	m_params = m_configured;
	m_params.cluster_radius_m = std::max(m_configured.cluster_radius_m, 16 * sigma);
	m_params.max_std_xy_m = std::max(m_configured.max_std_xy_m, 6 * sigma);
	m_ridgeRivals = sigma > 0;
}

size_t CPatchCorrelator::patchCells(const std::vector<Eigen::Vector2d>& patchPoints) const
{
	std::vector<int64_t> keys;
	keys.reserve(patchPoints.size());
	for (const auto& p : patchPoints) keys.push_back(cellKey(p, m_params.resolution_m));
	std::sort(keys.begin(), keys.end());
	return size_t(std::unique(keys.begin(), keys.end()) - keys.begin());
}

CCorrelationGrid CPatchCorrelator::makeGrid(const std::vector<Eigen::Vector2d>& pointsInMap,
											double margin) const
{
	return CCorrelationGrid::fromPoints(pointsInMap, m_params.resolution_m,
										m_params.blur_sigma_m, margin);
}

std::optional<TCorrelationResult> CPatchCorrelator::correlate(
	const CCorrelationGrid& oldMap, const std::vector<Eigen::Vector2d>& patchPoints,
	const mrpt::math::TPose2D& center, double halfWindowXY, double halfWindowTheta,
	TCorrelationEffort* effort) const
{
	return run(false, oldMap, patchPoints, center, halfWindowXY, halfWindowTheta, effort);
}

std::optional<TCorrelationResult> CPatchCorrelator::correlateExhaustive(
	const CCorrelationGrid& oldMap, const std::vector<Eigen::Vector2d>& patchPoints,
	const mrpt::math::TPose2D& center, double halfWindowXY, double halfWindowTheta) const
{
	return run(true, oldMap, patchPoints, center, halfWindowXY, halfWindowTheta, nullptr);
}

std::optional<TCorrelationResult> CPatchCorrelator::run(
	bool exhaustive, const CCorrelationGrid& grid,
	const std::vector<Eigen::Vector2d>& patchPoints, const mrpt::math::TPose2D& center,
	double halfWindowXY, double halfWindowTheta, TCorrelationEffort* effort) const
{
	TCorrelationEffort spent;
	if (!effort) effort = &spent;
	TPreparedSearch prepared;
	if (!prepareSearch(m_params, m_stop, grid, patchPoints, center, halfWindowXY,
					   halfWindowTheta, effort, prepared))
		return std::nullopt;
	const TGridSpec& spec = prepared.spec;
	const std::vector<Eigen::Vector2d>& pts = prepared.pts;
	const TPoseGridProblem& pb = prepared.pb;

	// Step 3: the best pose, scoring at least min_score.
	const auto search = [&](int64_t floor, const detail::TExclusionZone& z, bool firstHit)
	{
		return exhaustive ? detail::searchExhaustive(pb, floor, z)
						  : detail::searchBranchAndBound(pb, floor, z, firstHit);
	};
	const int64_t full = prepared.full;
	const auto floor1 =
		static_cast<int64_t>(std::ceil(m_params.min_score * double(full) - 1e-9));
	const detail::TSearchHit best = search(floor1, detail::TExclusionZone{}, false);
	effort->posesScored = best.evaluations;
	if (!best.found || best.stopped) return std::nullopt;
	TCorrelationResult res;
	res.patchInMap = spec.pose(best.a, best.i, best.j);
	res.score = double(best.score) / double(full);
	res.clusterPeaks.push_back({res.patchInMap, res.score});
	res.patchCells = pts.size();
	res.angularStep = spec.dtheta;

	// Step 4: the rival, outside the best cluster; ambiguity = s(best) / s(rival) (branch and
	// bound needs only to know whether a rival reaches s(best) / min_ambiguity).
	const int64_t floor2 =
		exhaustive ? 0
				   : static_cast<int64_t>(
						 std::ceil(double(best.score) / m_params.min_ambiguity - 1e-9));
	TRidge ridge;
	const TRidgeRule rule = m_ridgeRivals      ? TRidgeRule::AnyJoined
							: m_straightRidges ? TRidgeRule::Straight
											   : TRidgeRule::None;
	const detail::TSearchHit rival =
		detail::searchRival(search, m_params, rule, pb, spec, best, floor2, ridge);
	if (rival.stopped) return std::nullopt;  // a rival not found is no evidence then
	res.ambiguity = std::numeric_limits<double>::infinity();
	if (rival.found)
	{
		if (rival.score > 0) res.ambiguity = double(best.score) / double(rival.score);
		res.clusterPeaks.push_back(
			{spec.pose(rival.a, rival.i, rival.j), double(rival.score) / double(full)});
	}
	res.posesScored = best.evaluations + rival.evaluations;
	effort->posesScored = res.posesScored;

	// Step 5: the spread of the best cluster.
	res.cov = clusterCovariance(m_params, grid, pts, spec, best.a, best.i, best.j, best.score);
	res.ridgeAxis = ridge.axis;
	res.ridgeHalfLength = ridge.halfLength;
	res.ridgeMaxDeltaTheta = ridge.maxDeltaTheta;
	return res;
}

// The k best distinct poses in one best-first pass (detail::searchPeaks): each the best pose
// outside the clusters of the peaks before it, the floor max(min_score, atLeast) and, after
// the first, minShareOfBest s_1.
std::vector<TCorrelationPeak> CPatchCorrelator::correlatePeaks(
	const CCorrelationGrid& grid, const std::vector<Eigen::Vector2d>& patchPoints,
	const mrpt::math::TPose2D& center, double halfWindowXY, double halfWindowTheta, size_t k,
	double minShareOfBest, double atLeast, const TOriginRegion& origins,
	TCorrelationEffort* effort) const
{
	TCorrelationEffort spent;
	if (!effort) effort = &spent;
	std::vector<TCorrelationPeak> peaks;
	TPreparedSearch s;
	if (!prepareSearch(m_params, m_stop, grid, patchPoints, center, halfWindowXY,
					   halfWindowTheta, effort, s))
		return peaks;
	restrictOrigins(origins, s.spec, s.pb);
	const auto floor = static_cast<int64_t>(
		std::ceil(std::max(m_params.min_score, atLeast) * double(s.full) - 1e-9));
	detail::TExclusionZone zone;
	const detail::TSearchPeaks found = detail::searchPeaks(
		s.pb, floor, minShareOfBest, k, zone,
		[&](const detail::TSearchHit& hit)
		{ zone.discs.push_back(bestCluster(m_params, s.spec, s.pb.numAngles, hit)); });
	effort->posesScored = found.evaluations;
	for (const detail::TSearchHit& hit : found.peaks)
		peaks.push_back({s.spec.pose(hit.a, hit.i, hit.j), double(hit.score) / double(s.full)});
	return peaks;
}

}  // namespace lrgc
