/* CRevisitLinker: the end-of-run re-matching of revisited places (an extension of LRGC's
 * re-matching after a loop closure, paper 2.2, and of its final optimisation, 2.4).
 *
 * Online, a revisit is linked only when the gate finds the old poses within a Mahalanobis
 * distance of the estimate at that time; a stretch driven while the estimate was still off
 * (ACES: keyframes 661-730 revisit keyframes 87-98, but no candidate passed the gate then)
 * ends up placed by later closures elsewhere, without a direct link: its consistency with the
 * old map is then left to chance (relation error there 0.2-0.5 m in one run, 0.03 m in a
 * nearly identical one). After the run the map is loop-closed, so old and new poses that now
 * lie close together are a trustworthy guess:
 *   for every `stride`-th keyframe k, the nearest old keyframe j (index gap > min_index_gap)
 *   within `radius` and `max_phi_deg` of k's pose, not yet linked near (k, j) (no link
 *   between k +- 2 and j +- 2), is scan matched (guess: the current relative pose); where
 *   that fails and a quarter of j's scan is isolated returns (`region_retry`: a long-range
 *   laser's far walls, one return a metre, which no line fit holds), k is matched again
 *   against every old keyframe within 3 `radius` placed by the map, as a candidate facing
 *   away is. The match is kept if at least `min_inlier_fraction` of k's points matched and it
 * agrees with the guess (squared Mahalanobis distance <= gate_chi2, under the match covariance
 * plus a prior of `prior_std_xy_m` / `prior_std_phi_deg`); it becomes a LoopClosure link
 * (robust in the back-end, so a wrong one is down-weighted by the final optimisation). Frames:
 * poses (map <- robot) from the graph; links (from <- to). Units: m, rad.
 */
#pragma once

#include <lrgc/loop_closing/RevisitLinkerParams.h>
#include <lrgc/common/StopToken.h>
#include <lrgc/scan_matching/Keyframe.h>
#include <lrgc/pose_graph/LinkNoise.h>
#include <lrgc/pose_graph/PoseGraph.h>
#include <lrgc/scan_matching/ReferenceCloud.h>
#include <lrgc/scan_matching/ScanMatcher.h>
#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/core/bits_math.h>

#include <memory>
#include <optional>
#include <utility>
#include <vector>

namespace lrgc
{
class CRevisitLinker
{
public:
	CRevisitLinker(const TRevisitLinkerParams& p, const TScanMatcherParams& matcher,
				   const TLinkNoise& linkNoise);

	/** Adds the revisit links to `graph` (no optimisation); returns how many. Once `stop`
	 * (setStopToken) is stopped, the sweep ends: the links added until then stay. */
	size_t linkRevisits(CPoseGraph& graph, const TKeyframes& keyframes) const;
	void setStopToken(const CStopToken& stop) { m_stop = stop; }
	/** Nodes below `split` and nodes from it on are in frames of their own (a session mapped
	 * as a piece not joined to the map): no pair across it is linked. 0: one frame. */
	void setSplit(size_t split) { m_split = split; }
	/** Whether the match fixes its heading at its own position (the heading's std with the
	 * translation held, 1 / sqrt(Omega_phiphi)) to max_heading_std; a revisit match that does
	 * not is never linked. */
	bool fixesItsHeading(const TScanMatch& m) const;

private:
	struct TSweep;
	struct TCandidate
	{
		size_t old = 0;             //!< the old keyframe the link starts from
		mrpt::math::TPose2D guess;  //!< (old <- k) by the current poses
		/** In old's frame; shared, so that a check's match may defer its covariance. */
		std::shared_ptr<const CReferenceCloud> reference;
		bool single = false;  //!< the reference is old's scan alone (a same-heading candidate)
	};
	std::vector<std::pair<size_t, double>> oldNear(const TSweep& sw, size_t k,
												   double reach) const;
	std::optional<TCandidate> candidate(const TSweep& sw, const TKeyframes& keyframes, size_t k,
										const TParallelFor& parallel) const;
	/** k's match against c's reference; where that fails on a single old scan of mostly
	 * isolated returns (region_retry), c's reference becomes the old map's region and k is
	 * matched again against it. */
	std::optional<TScanMatch> matchCandidate(const TSweep& sw, const TKeyframes& keyframes,
											 size_t k, TCandidate& c,
											 const TParallelFor& parallel) const;
	/** k's patch (keyframes k +- patch_check_keyframes in k's frame) and the old map's region
	 * (old's frame) where it falls at a pose of k in old's frame. */
	struct TPatch
	{
		TScan2D patch;
		std::shared_ptr<const CReferenceCloud> region;
	};
	TPatch patchOf(const TSweep& sw, const TKeyframes& keyframes, size_t k, size_t old,
				   const mrpt::math::TPose2D& at, const TParallelFor& parallel) const;
	bool patchAgrees(const TPatch& p, const TScanMatch& m) const;
	CReferenceCloud oldRegion(const TSweep& sw, const TKeyframes& keyframes, size_t k,
							  size_t old, const std::vector<Eigen::Vector2d>& points,
							  const mrpt::math::TPose2D& at, const TParallelFor& parallel,
							  bool withViews) const;
	bool rivalFrom(const TScan2D& scan, const TCandidate& c, const TScanMatch& m,
				   const Eigen::Matrix3d& prior, double explained,
				   const mrpt::math::TPose2D& offset) const;
	bool passesChecks(const TSweep& sw, const TKeyframes& keyframes, size_t k,
					  const TCandidate& c, const TScanMatch& m, const Eigen::Matrix3d& prior,
					  const TParallelFor& parallel) const;

	TRevisitLinkerParams m_params;
	TScanMatcherParams m_matcherParams;
	TLinkNoise m_linkNoise;
	CScanMatcher m_matcher;
	CScanMatcher m_patchMatcher;  //!< no free-space test: a patch is not one scan's rays
	CStopToken m_stop;
	size_t m_split = 0;
};

}  // namespace lrgc
