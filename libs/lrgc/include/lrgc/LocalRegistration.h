/* CLocalRegistration: LRGC's local registration (Gutmann & Konolige, section 2.2, use 1).
 *
 * Each new scan is matched against a local patch made of the last K keyframes' scans (in the
 * frame of the newest keyframe), which gives its pose. When the scan becomes a keyframe it is
 * linked to the previous keyframe by odometry and to every window keyframe it overlaps by a
 * pairwise scan match, and consistent pose estimation (Lu & Milios 1997) over the window only
 * adjusts the last K poses, all older poses held fixed: constant cost per scan.
 *
 * Odometry glitches (the benchmark logs have single steps turning 60-85 deg wrongly): when the
 * match from the odometry prior fails and the prior is suspect (its step turns more than
 * glitch_min_turn, or matching has failed `wide_after_failures` scans in a row), a wide
 * rotational search around the prior is tried (CScanMatcher::matchWide: tens of ms, and a
 * symmetric corridor can fool it, so only then). Otherwise the prior is kept for that scan. Whenever the accepted match disagrees
 * with the prior beyond a chi-square gate, the odometry of that step is not trusted: the
 * odometry link of the keyframe is down-weighted to the constant-velocity noise, so it cannot
 * pull the map.
 *
 * Cost per keyframe: one patch build, at most `max_pairwise_links` pairwise matches against
 * reference clouds cached per window keyframe, and a window solve; none depends on the map
 * size.
 */
#pragma once

#include <lrgc/Keyframe.h>
#include <lrgc/LinkNoise.h>
#include <lrgc/PoseGraph.h>
#include <lrgc/PoseGraphOptimizer.h>
#include <lrgc/ReferenceCloud.h>
#include <lrgc/ScanMatcher.h>
#include <mrpt/config/CLoadableOptions.h>

#include <deque>
#include <optional>
#include <utility>

namespace lrgc
{
struct TLocalRegistrationParams : public mrpt::config::CLoadableOptions
{
	size_t window_size = 10;  //!< K: keyframes in the window (paper: K >= 7 at 0.3 m)
	size_t max_pairwise_links = 5;  //!< pairwise scan-match links per new keyframe (spread over the window)
	double min_link_inliers = 0.5;  //!< pairwise link only if this fraction of points matched
	double glitch_gate_chi2 = 16.27;  //!< [chi2, 3 dof] prior/match disagreement (p = 0.001)
	double wide_search_angle = mrpt::DEG2RAD(90.0);  //!< [rad] (key wide_search_angle_deg)
	double glitch_min_turn = mrpt::DEG2RAD(30.0);  //!< [rad] a step turning more is suspect (key glitch_min_turn_deg)
	size_t wide_after_failures = 3;  //!< or this many failed matches in a row
	/** Free-space tolerance of local matches, replacing [ScanMatcher]'s: with an odometry
	 * prior a wrong match is unlikely, while people walking through the window's scans and
	 * glass make the strict loop-closing value reject good local matches on real logs. */
	double max_free_space_violation = 0.3;
	TLinkNoise link_noise;  //!< keys link_floor_xy [m], link_floor_phi_deg (see LinkNoise.h)

	void loadFromConfigFile(
		const mrpt::config::CConfigFileBase& c, const std::string& s) override;
	void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

/** Pose of one scan from the local registration. */
struct TRegistration
{
	mrpt::math::TPose2D scanInMap;  //!< (map <- robot at the scan)
	Eigen::Matrix3d cov;  //!< of the scan pose relative to the newest keyframe, map axes
	bool matched = false;  //!< false: no acceptable match, the prior was kept
	bool odometryRejected = false;  //!< the match disagrees with the prior beyond the gate
	bool wideSearch = false;  //!< the match came from the wide rotational search
};

class CLocalRegistration
{
   public:
	CLocalRegistration(
		const TLocalRegistrationParams& p, const TScanMatcherParams& matcher,
		const TPoseGraphOptimizerParams& optimizer);

	/** Matches `scan` against the window of the newest keyframes of `graph`.
	 * priorInMap / priorCov: the motion prediction composed onto the previous scan's pose. */
	TRegistration registerScan(
		const CPoseGraph& graph, const TKeyframes& keyframes, const TScan2D& scan,
		const mrpt::math::TPose2D& priorInMap, const Eigen::Matrix3d& priorCov,
		double priorStepTurn);

	/** Links the newest node (just added to `graph` at its registered pose) to the window:
	 * `odometryLink` (from the previous keyframe) plus pairwise scan matches, then optimises
	 * the window. Returns the number of scan-match links added. */
	size_t linkAndOptimize(
		CPoseGraph& graph, const TKeyframes& keyframes, const TLink& odometryLink);

	/** Poses changed outside the window (loop closure): rebuild the patch on next use. */
	void invalidate() { m_cloudNewest.reset(); }

   private:
	std::vector<size_t> windowNodes(const CPoseGraph& graph) const;
	const CReferenceCloud& windowCloud(const CPoseGraph& graph, const TKeyframes& keyframes);

	TLocalRegistrationParams m_params;
	TScanMatcherParams m_matcherParams;
	CScanMatcher m_matcher;
	CPoseGraphOptimizer m_optimizer;
	const CReferenceCloud& keyframeCloud(size_t node, const TKeyframes& keyframes);

	CReferenceCloud m_cloud;  //!< window patch in the frame of node *m_cloudNewest
	std::optional<size_t> m_cloudNewest;
	size_t m_failuresInARow = 0;
	/** Reference cloud of each window keyframe's own scan, for pairwise links. */
	std::deque<std::pair<size_t, CReferenceCloud>> m_keyframeClouds;
};

}  // namespace lrgc
