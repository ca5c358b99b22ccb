/* CPatchCorrelator: global correlation of a map patch (the newest scans) against the old map
 * (Gutmann & Konolige, section 2.3), with the paper's three false-positive filters.
 *
 * Operator: for a pose l = (x, y, theta) of the patch in the map, with the patch reduced to
 * its N distinct occupied cells p_k (cells of `resolution` in the patch frame; centroid of
 * the points in each), the unnormalised score is
 *     s(l) = 1/N sum_k p_m( cell( R(theta) p_k + t ) )   in [0,1],
 * the paper's sum_i p(r_i) p(m_i) with p(r_i) = 1 on patch cells and all uncertainty folded
 * into the blurred map p_m (CCorrelationGrid).
 *
 * Pose grid: theta_a = theta_c + a dtheta (a = -A..A), t = t_c + (i, j) resolution
 * (i, j = -W..W), W = ceil(halfWindowXY / resolution), A = ceil(halfWindowTheta / dtheta)
 * (the whole circle, once, if the window reaches +-pi).
 *
 * correlateExhaustive() scores every pose of the grid (the paper's reference). correlate()
 * returns the same best pose by branch and bound: for each angle, 2^h x 2^h blocks of
 * translations are bounded by the level-h max-pooled grid (an upper bound of every score in
 * the block, so pruning a block whose bound is below the best score found loses nothing);
 * ties are broken towards the lowest (a, i, j) in both searches. Details, proofs and timings:
 * doc/global-correlation.md.
 */
#pragma once

#include <lrgc/loop_closing/CorrelationGrid.h>
#include <lrgc/common/StopToken.h>
#include <lrgc/loop_closing/PatchCorrelatorParams.h>
#include <mrpt/math/TPose2D.h>

#include <Eigen/Core>
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace lrgc
{
struct TCorrelationPeak
{
	mrpt::math::TPose2D patchInMap;  //!< (map <- patch)
	double score = 0;                //!< s(l) in [0,1]
};

/** Outcome of the three filters; `rejection` names the first that failed. */
struct TCorrelationVerdict
{
	enum class Reason
	{
		Accepted,
		LowScore,    //!< value = score, limit = min_score
		Ambiguous,   //!< value = ambiguity, limit = min_ambiguity
		SpreadXY,    //!< value = largest std dev of x, y [m], limit = max_std_xy_m
		SpreadTheta  //!< value = std dev of heading [rad], limit = max_std_phi
	};
	Reason rejection = Reason::Accepted;
	double value = 0;
	double limit = 0;
	bool accepted() const { return rejection == Reason::Accepted; }
	/** One line for a log, e.g. "ambiguity 1.04 < min_ambiguity 1.15". */
	std::string message() const;
};

struct TCorrelationResult
{
	mrpt::math::TPose2D patchInMap;  //!< best pose (map <- patch)
	double score = 0;                //!< s(best) in [0,1]
	/** s(best) / s(best pose outside the best cluster), exact from correlateExhaustive().
	 * From correlate(): +inf when no pose outside the cluster reaches s(best) /
	 * min_ambiguity (the value is then only known to be > min_ambiguity); otherwise the ratio
	 * to the first such pose found, in [exact, min_ambiguity]: either way the verdict of
	 * filter 2 is the exact one. */
	double ambiguity = 0;
	/** Covariance of patchInMap [m^2, rad^2] from the normalised response around the peak
	 * (see TPatchCorrelatorParams::cluster_score_scale), plus the grid's discretisation. */
	Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
	/** Best cluster's peak, then the rival when known (outside the cluster; see ambiguity). */
	std::vector<TCorrelationPeak> clusterPeaks;

	/** Rivals on one straight ridge through the best pose (a corridor's slide, joined to it
	 * without a valley; noise-free lasers, see CPatchCorrelator::correlate) belong to the best
	 * peak: the ridge's unit axis [map frame] (zero: none), its half-length from the best
	 * pose [m] and the rivals' largest heading difference [rad]. Filter 3 then judges the
	 * spread across the axis; ridgeCovariance() is what the position along it is worth. */
	Eigen::Vector2d ridgeAxis = Eigen::Vector2d::Zero();
	double ridgeHalfLength = 0, ridgeMaxDeltaTheta = 0;
	/** Covariance of the pose along the ridge [map frame; m^2, rad^2]: its half-length at 2
	 * sigma along the axis, half the heading difference as a std; zero without a ridge. */
	Eigen::Matrix3d ridgeCovariance() const;

	size_t patchCells = 0;   //!< N: distinct patch cells scored
	double angularStep = 0;  //!< dtheta of the pose grid [rad]
	size_t posesScored = 0;  //!< exact scores + block bounds evaluated (search effort)

	TCorrelationVerdict checkFilters(const TPatchCorrelatorParams& p) const;
	bool passesFilters(const TPatchCorrelatorParams& p) const
	{
		return checkFilters(p).accepted();
	}
};

/** What a search cost, known even when it found nothing (TLoopWork counts it). */
struct TCorrelationEffort
{
	size_t headings = 0;     //!< headings of the pose grid
	size_t patchCells = 0;   //!< N: distinct patch cells
	size_t posesScored = 0;  //!< exact scores + block bounds evaluated
	/** If set, called once headings and patchCells are known, before the search, and as
	 * the search goes on (posesScored so far). */
	std::function<void(const TCorrelationEffort&)> onProgress;
};

/** Where a search may put the patch's origin (the newest keyframe): within `radius` [m] of
 * one of `points` [map frame]. The far loop search gives the old keyframes' positions, since a
 * revisit stands about where the robot stood before. No points: anywhere in the window.
 * beyondXY > 0 keeps only a square ring of the window: translations more than beyondXY [m]
 * from the window's centre in x or y (max(|i|, |j|) > ceil(beyondXY / resolution) cells), so
 * that the far search can ask for its best places ring by ring. */
struct TOriginRegion
{
	std::vector<Eigen::Vector2d> points;
	double radius = 0;
	double beyondXY = 0;
};

class CPatchCorrelator
{
public:
	/** Validates the parameters (throws naming the bad key). */
	explicit CPatchCorrelator(const TPatchCorrelatorParams& params = {});

	const TPatchCorrelatorParams& params() const { return m_params; }
	/** Scales the best cluster and filter 3 to scans of range noise `sigma` [m] (TScan2D::
	 * rangeNoiseStd): cluster_radius_m = max(configured, 16 sigma), max_std_xy_m =
	 * max(configured, 6 sigma). Noise spreads the correlation peak in proportion, so a
	 * constant radius cuts the one peak into "best" and an adjacent "rival" (measured on MRPT's
	 * range_030_bearing_015 log: the rival 0.5-1 m along the peak's ridge,
	 * ambiguity 1.02-1.198). The radius alone does not hold a corridor's ridge (the synthetic
	 * noisy ring: rivals 0.8 m along it, ambiguity 1.18-1.19 with a radius of 0.78 m), so for
	 * sigma > 0 a rival joined to the best pose by poses all scoring at least s(best) /
	 * min_ambiguity (no valley between them) is the best peak's own: its cluster joins the
	 * best's and the rival search goes on (up to 8 times), leaving the ridge's extent to filter
	 * 3. sigma is 0 unless the laser is noisy (kNoisyLaserStd_m): the configured values. */
	void setScanNoise(double sigma);
	/** Whether rivals on one straight line through the best pose join its peak
	 * (TCorrelationResult::ridgeAxis; rival_search.h, TRidgeRule::Straight): the loop
	 * closer's near search, whose link carries the ridge's doubt. Off (the paper's filter 2
	 * for every rival) unless set; a noisy laser's own ridge rule (setScanNoise) comes first.
	 */
	void setStraightRidges(bool on) { m_straightRidges = on; }

	/** Searches end early once `stop` is stopped and then find nothing (std::nullopt). */
	void setStopToken(const CStopToken& stop) { m_stop = stop; }
	const CStopToken& stopToken() const { return m_stop; }

	/** N: the distinct cells (of resolution_m, in the patch frame) that `patchPoints` occupy,
	 * the cells a search scores (TCorrelationEffort::patchCells). */
	size_t patchCells(const std::vector<Eigen::Vector2d>& patchPoints) const;

	/** The old-map grid with this correlator's resolution and blur; `margin` [m] around the
	 * points' bounding box (at least 3 sigma keeps the blur of edge walls). */
	CCorrelationGrid makeGrid(const std::vector<Eigen::Vector2d>& pointsInMap,
							  double margin) const;

	/** Branch and bound over the pose grid centred on `centerPatchInMap` (map <- patch):
	 * x, y within +-halfWindowXY [m], heading within +-halfWindowTheta [rad]. `patchPoints`
	 * are in the patch frame. Returns std::nullopt if no pose scores at least min_score (the
	 * score filter fails), or if the patch is empty. The result is the exhaustive one;
	 * filters are not applied (see checkFilters). The grid's resolution is used. If
	 * `effort` is given, the search's effort is written there. */
	std::optional<TCorrelationResult> correlate(const CCorrelationGrid& oldMap,
												const std::vector<Eigen::Vector2d>& patchPoints,
												const mrpt::math::TPose2D& centerPatchInMap,
												double halfWindowXY, double halfWindowTheta,
												TCorrelationEffort* effort = nullptr) const;

	/** The k best distinct poses of the same pose grid, best first, by branch and bound:
	 * peak n is the best pose outside the clusters (cluster_radius_m, cluster_radius_phi) of
	 * peaks 1..n-1, scoring at least min_score, `atLeast` and minShareOfBest times peak 1's
	 * score, with the patch's origin in `origins` (empty: anywhere). No filter is applied.
	 * Empty if no pose reaches the floor, the patch is empty or a stop was requested. One
	 * best-first pass (detail::searchPeaks): about one correlate() for all k peaks, where
	 * searching again per peak cost that much per peak (30-60k bounds each on the hall loop).
	 */
	std::vector<TCorrelationPeak> correlatePeaks(
		const CCorrelationGrid& oldMap, const std::vector<Eigen::Vector2d>& patchPoints,
		const mrpt::math::TPose2D& centerPatchInMap, double halfWindowXY,
		double halfWindowTheta, size_t k, double minShareOfBest, double atLeast = 0,
		const TOriginRegion& origins = {}, TCorrelationEffort* effort = nullptr) const;

	/** The paper's exhaustive search over the same pose grid; same contract, except that the
	 * ambiguity is always the exact ratio (inf only if every pose is inside the cluster). */
	std::optional<TCorrelationResult> correlateExhaustive(
		const CCorrelationGrid& oldMap, const std::vector<Eigen::Vector2d>& patchPoints,
		const mrpt::math::TPose2D& centerPatchInMap, double halfWindowXY,
		double halfWindowTheta) const;

private:
	std::optional<TCorrelationResult> run(bool exhaustive, const CCorrelationGrid& oldMap,
										  const std::vector<Eigen::Vector2d>& patchPoints,
										  const mrpt::math::TPose2D& center,
										  double halfWindowXY, double halfWindowTheta,
										  TCorrelationEffort* effort) const;

	TPatchCorrelatorParams m_configured;  //!< as given
	TPatchCorrelatorParams m_params;      //!< as used: m_configured scaled by setScanNoise
	/** A noisy laser's (setScanNoise): rivals on the best peak's ridge join its cluster. */
	bool m_ridgeRivals = false;
	bool m_straightRidges = false;  //!< setStraightRidges()
	CStopToken m_stop;
};

}  // namespace lrgc
