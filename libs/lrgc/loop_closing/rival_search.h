/* Step 4 of a global correlation query (Gutmann & Konolige 2000, section 2.3, filter 2;
 * PatchCorrelator.cpp has the steps): the rival search outside the best pose's cluster, and the
 * ridge rules by which a rival on the best peak's own ridge joins its cluster instead of
 * failing filter 2. Frames: the pose grid's (pose_grid.h); units: m, rad, grid cells. Not
 * installed (a detail of PatchCorrelator.cpp).
 */
#pragma once

#include <lrgc/loop_closing/PatchCorrelatorParams.h>

#include "correlation_search.h"
#include "pose_grid.h"

#include <Eigen/Core>
#include <cstdint>
#include <functional>

namespace lrgc::detail
{
/** How step 4 treats a rival as good as s(best) / min_ambiguity or better. */
enum class TRidgeRule
{
	None,  //!< it is the rival (the paper's filter 2)
	/** A noisy laser's (CPatchCorrelator::setScanNoise): the peak is as wide as the noise; a
	 * rival that the poses scoring at least s(best) / min_ambiguity join to the best without a
	 * valley (joinedAbove) lies on the best peak's ridge, its cluster joins the best's, and
	 * filter 3 judges the ridge's extent. */
	AnyJoined,
	/** The loop closer's near search (CPatchCorrelator::setStraightRidges) for every other
	 * laser: a rival on one straight line through the best pose (heading within max_std_phi of
	 * the best's, within cluster_radius_m of the line from the best to the first such rival), a
	 * cluster radius or more inside the window's border, belongs to the best's peak, with a
	 * valley between them or not: a slide along a corridor, whose look-alikes (the next bay,
	 * door or column along it) agree with the best on the heading and on the place across the
	 * corridor. How far along the line they reach is the loop link's doubt
	 * (TCorrelationResult::ridgeCovariance). A rival off that line stays the rival (filter 2),
	 * and so does one near the border: the line may go on outside the window, the true place
	 * with it. So does the first rival on the line where its step leaves the window's centre
	 * (the gate's prediction) more than a cluster radius beyond the ridge's reach: look-alikes
	 * along a corridor away from where the robot is predicted, the true place perhaps a
	 * stretch the patch matches less well (and no further rival search is spent on them). */
	Straight
};

/** The rivals joined to the best pose (TRidgeRule::Straight): the ridge's axis and extent. */
struct TRidge
{
	Eigen::Vector2d axis = Eigen::Vector2d::Zero();  //!< unit, map frame; zero: none joined
	double halfLength = 0;                           //!< [m] farthest joined rival + radius
	double maxDeltaTheta = 0;                        //!< [rad] of the joined rivals
};

/** Step 4's exclusion zone: the best pose's cluster, the headings within cluster_radius_phi_deg
 * and the cells within cluster_radius_m of it [cells^2]. */
TExclusionDisc bestCluster(const TPatchCorrelatorParams& prm, const TGridSpec& spec,
						   int numAngles, const TSearchHit& best);

/** One search of the pose grid (searchExhaustive or searchBranchAndBound): the best pose
 * scoring at least `floor` outside `zone`, the first to reach it if `firstHit`. */
using TRivalSearch =
	std::function<TSearchHit(int64_t floor, const TExclusionZone& zone, bool firstHit)>;

/** Step 4's search, outside the best cluster. A rival on the best peak's ridge (TRidgeRule)
 * has its cluster join the best's, and the search goes on for a peak of its own; the straight
 * ridge's extent is returned in `ridge`. */
TSearchHit searchRival(const TRivalSearch& search, const TPatchCorrelatorParams& prm,
					   TRidgeRule rule, const TPoseGridProblem& pb, const TGridSpec& spec,
					   const TSearchHit& best, int64_t floor, TRidge& ridge);

}  // namespace lrgc::detail
