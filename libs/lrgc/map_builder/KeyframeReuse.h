/* CKeyframeReuse: no new keyframes on ground the map already has (issue 12).
 *
 * A scan becomes a keyframe after keyframe_distance_m of travel or keyframe_angle of turn from
 * where the robot took the keyframe it is at ([MapBuilder]). On a revisit that keyframe would
 * duplicate one the map already holds, and a robot that keeps driving the same building would
 * grow its graph, its loop searches and its memory with the time driven. Instead, as in the
 * reduced pose graph of Johannsson et al. (2013), the scan takes an existing keyframe c as its
 * anchor when c covers its pose, i.e. the pose would not be a new keyframe relative to c:
 *     |t(X_c^-1 (+) X_scan)| < keyframe_distance_m  and  |phi(X_c^-1 (+) X_scan)| <
 * keyframe_angle, the nearest such c (in units of those two). The scans hang from c, c enters
 * the local window (CLocalRegistration::enterKeyframe), so the next scans are registered
 * against the map's own keyframes there, and the builder links the previous anchor to c by the
 * scan's two matches (the revisit's evidence is kept as a link, not as a node). The graph then
 * grows with the area covered at the keyframe spacing, not with the time driven.
 *
 * Reusing c asserts that the robot's estimate agrees with the map at c, which holds only after
 * a loop link has tied the robot's recent keyframes to the map (the loop closer's three
 * filters, section 2.3): keyframes are reused only within trust_keyframes new keyframes of the
 * last loop link, and only ones outside the local window (a robot backing up over its newest
 * keyframes makes new ones, as without reuse: the window solve must stay free to move them;
 * so local registration alone, with no loop links, is unchanged). The scan must also match
 * c's own scan (min_inlier_fraction) where its registration puts it,
 * within gate_chi2 under the match covariance, the registration's and the loop links' noise
 * floor (scans taken at other times). Otherwise a new keyframe is made, as without reuse.
 * A wider cover (1 m, 30 deg) was measured and not adopted: doc/back-end.md.
 * Cost: one pass over the node positions and one scan match per keyframe decision.
 * Frames: poses (map <- robot) [m, rad].
 */
#pragma once

#include <lrgc/scan_matching/ScanMatcher.h>
#include <lrgc/map_builder/KeyframeReuseParams.h>
#include <lrgc/scan_matching/Keyframe.h>
#include <lrgc/pose_graph/LinkNoise.h>
#include <lrgc/pose_graph/PoseGraph.h>

#include <Eigen/Core>
#include <deque>
#include <optional>

namespace lrgc
{
/** A keyframe to reuse, and the scan matched against its scan. */
struct TReusedKeyframe
{
	size_t node = 0;
	mrpt::math::TPose2D scanInNode;  //!< (node <- robot at the scan), from the match
	Eigen::Matrix3d cov;             //!< of scanInNode, in the node's axes
};

class CKeyframeReuse
{
public:
	/** keyframeDistance [m], keyframeAngle [rad]: [MapBuilder]'s keyframe spacing, the
	 * cover of a keyframe; matcher: the local registration's; floor: the loop links' noise
	 * floor. */
	CKeyframeReuse(const TKeyframeReuseParams& p, double keyframeDistance, double keyframeAngle,
				   const TScanMatcherParams& matcher, const TLinkNoise& floor);

	/** A loop link entered the graph while `node` was the newest keyframe. The map builder
	 * passes the newest keyframe when the worker's result arrives, not the link's own end:
	 * a result lands up to [LoopCloser] max_backlog_keyframes keyframes after its search, and
	 * the keyframes since are carried along by its correction. */
	void noteLoopLink(size_t node);
	/** Keyframes below `first` are no candidates: they belong to a map the robot is not yet
	 * placed in (a session mapped as a piece of its own, in its own frame); 0: all are. */
	void setFirstCandidate(size_t first) { m_firstCandidate = first; }
	/** Its scan matches end early, matching nothing, once `stop` is stopped. */
	void setStopToken(const CStopToken& stop) { m_matcher.setStopToken(stop); }

	/** The existing keyframe to anchor `scan` at instead of making it a new keyframe, if one
	 * covers `scanInMap` and may be trusted. anchor: the keyframe the robot is at (not a
	 * candidate); window: the local window's keyframes; scanCov: covariance of the scan's
	 * registered pose [map axes], read only where a candidate's match is found (it may be a
	 * deferred one, TRegistration::cov). Keyframes in the window are not candidates. */
	std::optional<TReusedKeyframe> reusableKeyframe(
		const CPoseGraph& graph, const TKeyframes& keyframes, const TScan2D& scan,
		const mrpt::math::TPose2D& scanInMap, const CLazyCovariance& scanCov, size_t anchor,
		const std::deque<size_t>& window) const;

private:
	TKeyframeReuseParams m_params;
	double m_distance, m_angle;
	CScanMatcher m_matcher;
	TLinkNoise m_floor;
	std::optional<size_t> m_lastLinked;  //!< newest node with a loop link
	size_t m_firstCandidate = 0;
};

}  // namespace lrgc
