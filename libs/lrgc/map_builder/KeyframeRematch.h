/* CKeyframeRematcher: the end-of-run re-match of the keyframes local registration could not
 * match (issue 28 item 4, every scan's pose final; an extension of LRGC's final optimisation,
 * paper 2.4).
 *
 * A keyframe whose scan matched nothing online keeps its predicted pose: the odometry chain
 * from the previous scan. Where the odometry failed (a sparse log's step after a pause that
 * reads -48 deg where the robot turned -104: ACES sparse, keyframe at 613.04 s) that pose is
 * tens of degrees off, and only the odometry links hold the node, so the final optimisation
 * leaves it there. Online, its scan was matched against a window that had seen the place from
 * the other side; after the run the map holds the keyframes that came later too.
 *
 * For each such keyframe k (`candidates`, in the order given):
 *   1. the reference: the scans of the keyframes within kNeighbourRadius of k's position,
 *      placed at their poses in the frame of the nearest of them, r. The other unmatched
 *      keyframes are among them (ACES sparse: six in a row at that corner, five of them
 *      placed right by the odometry; without them the reference is two keyframes seen from
 *      the other side): one whose pose is off offers a second, distinct hypothesis, which
 *      the evidence below refuses rather than follows;
 *   2. CScanMatcher::matchWide of k's scan from its current pose relative to r over +-
 *      `wideAngle` of heading (the odometry's failure a glitch can span online,
 *      [LocalRegistration] wide_search_angle), with its standard of evidence (a clear
 *      majority of the scan matched, a clear lead over every other heading and over the local
 *      optimum at the current pose itself); no evidence, or a winner in the current pose's
 *      own basin (CScanMatcher::distinctHypotheses): k is left where it is;
 *   2b. the map must agree with itself there: the reference's keyframes, cut into visits (runs
 *      of indices at most kVisitGap apart: the robot's passes through the place), each match
 *      k's scan alone from the winner; one that converges elsewhere (beyond glitch_gate_chi2
 *      under both covariances and the loop links' floor) says the visits are not aligned at
 *      this place, and the link, read in r's frame, would carry their offset: k is left where
 *      it is (the glass atrium's corners, three laps 0.1-0.3 m apart, where every re-match
 *      landed 0.34-0.57 m off the truth, doc/generalisation.md);
 *   3. a winner moves k there and links it to r by a loop-closure link (robust in the final
 *      optimisation), and each odometry or window link of k that the new pose contradicts
 *      (chi2 under the link's covariance > glitch_gate_chi2, or a distinct hypothesis) is
 *      down-weighted to the constant-velocity noise at the relative pose as it now stands, as
 *      local registration does online after a wide-search override: the odometry that
 *      failed, and the patch link made in k's frame while k was off, can no longer pull k
 *      back (in UnmatchedKeyframe's room, with the odometry links alone down-weighted, the
 *      scans after the turn followed that patch link 81 deg off).
 * An unmatched keyframe without evidence stays on its odometry prior: the scan never bends the
 * map (issue 28 item 3). The final optimisation then places every keyframe.
 * The session's first keyframe goes through the same steps
 * (CMetricMapBuilderLRGC::rematchFirstKeyframe): online, only the next keyframes were matched
 * against it, each against it alone, and one wrong match there turns the whole map about the
 * start.
 * Frames: poses (map <- robot); links (from <- to). Units: m, rad.
 */
#pragma once

#include <lrgc/scan_matching/Keyframe.h>
#include <lrgc/common/StopToken.h>
#include <lrgc/pose_graph/LinkNoise.h>
#include <lrgc/pose_graph/PoseGraph.h>
#include <lrgc/scan_matching/ScanMatcher.h>
#include <mrpt/math/TPose2D.h>

#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace lrgc
{
/** A keyframe the re-match moved: its node and its pose before (map frame). */
struct TRematchedKeyframe
{
	size_t node = 0;
	mrpt::math::TPose2D before;
};

class CKeyframeRematcher
{
public:
	/** `matcher`: [ScanMatcher] (its strict free-space test, as loop closing's); `wideAngle`
	 * [rad]: the heading searched either side; `gateChi2`: an odometry link contradicted
	 * beyond it is down-weighted to `weakOdometryCov` [m^2, rad^2]; `linkNoise`: the loop
	 * links' noise floor. */
	CKeyframeRematcher(const TScanMatcherParams& matcher, double wideAngle, double gateChi2,
					   const Eigen::Matrix3d& weakOdometryCov, const TLinkNoise& linkNoise);

	/** Re-matches each of `candidates` (nodes of `graph`, scans in `keyframes`) as above;
	 * nodes below `split` and from it on are in frames of their own (a piece not joined):
	 * no reference across it. Returns the keyframes moved. Once `stop` (setStopToken) is
	 * stopped, the re-match ends: the keyframes moved until then stay moved. */
	std::vector<TRematchedKeyframe> rematch(CPoseGraph& graph, const TKeyframes& keyframes,
											const std::vector<size_t>& candidates,
											size_t split = 0) const;
	void setStopToken(const CStopToken& stop)
	{
		m_stop = stop;
		m_matcher.setStopToken(stop);
	}

private:
	/** Step 2's second opinion (KeyframeRematch.cpp): k's scan, matched from the winner `m`
	 * (r <- k) against each visit of the place among `near` alone, stays there. */
	bool visitsAgree(const CPoseGraph& graph, const TKeyframes& keyframes, size_t k, size_t r,
					 const std::vector<size_t>& near, const TScanMatch& m,
					 const TParallelFor& parallel) const;
	/** Step 3: k placed where `m` (r <- k) puts it, linked to r, its contradicted odometry
	 * weakened. */
	void relink(CPoseGraph& graph, const TKeyframes& keyframes, size_t k, size_t r,
				const TScanMatch& m) const;

	TScanMatcherParams m_params;
	CScanMatcher m_matcher;
	double m_wideAngle;
	double m_gateChi2;
	Eigen::Matrix3d m_weakOdometryCov;
	TLinkNoise m_linkNoise;
	CStopToken m_stop;
};

}  // namespace lrgc
