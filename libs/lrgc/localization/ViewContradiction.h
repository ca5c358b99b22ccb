/* CViewContradiction: does a scan contradict the map where it is thought to be, pass by pass?
 *
 * Tracking's reference cloud joins the nearest map keyframes, taken on several passes. Where
 * the world changed between passes (a door open on one and shut on another, people, a cart),
 * a scan at the right pose puts some walls where one pass saw free space and others where
 * another did: against the joined cloud 30-59 % of it violates free space, yet against each
 * pass on its own it agrees (MIT Killian localised on its own map: 8 of its 11 false kidnaps).
 * A robot carried off contradicts every pass near where it is thought to be. So a scan
 * contradicts the map only if it contradicts each pass (a run of keyframe indices) on its
 * own. Not each keyframe on its own: one keyframe sees too little of the place, and Intel's
 * 25 m kidnap then agreed with one of them and was never detected.
 * Frames: poses (map <- robot) [m, rad].
 */
#pragma once

#include <lrgc/scan_matching/ScanMatcherParams.h>
#include <lrgc/pose_graph/PoseGraph.h>
#include <lrgc/scan_matching/Keyframe.h>
#include <lrgc/scan_matching/ReferenceCloud.h>

#include <map>
#include <utility>
#include <vector>

namespace lrgc
{
class CViewContradiction
{
public:
	/** Keyframes of one pass: indices at most kPassGap apart (a pass adds its keyframes in
	 * a row); passes of fewer than kMinPassKeyframes near the scan (one that only grazed the
	 * place, whose few views cover too little of it to contradict anything) are not asked. */
	static constexpr size_t kPassGap = 2, kMinPassKeyframes = 3;
	/** A long pass is asked in parts of at most this many keyframes (a remainder shorter
	 * than kMinPassKeyframes joins the last part): on MIT Killian, where the robot stood and
	 * turned for seconds, 20 keyframes of one pass near the scan disagreed among themselves
	 * as passes do (3 false kidnaps). 6 delayed Intel's kidnap detection 1.1 -> 5.0 s. */
	static constexpr size_t kMaxPassKeyframes = 10;
	/** Pass clouds kept for the next scans (the passes of the current reference). */
	static constexpr size_t kMaxCachedPasses = 32;

	/** `map` and `keyframes` must outlive this object. */
	CViewContradiction(const CPoseGraph& map, const TKeyframes& keyframes,
					   const TScanMatcherParams& params);

	/** True if `scan` at `pose` violates free space by at least `fraction` against each
	 * pass of the keyframes `nodes` on its own (CReferenceCloud::freeSpaceViolation with
	 * `margin`); false as soon as one agrees. No pass asked: true (the joined cloud's word). */
	bool contradictsEveryPass(const TScan2D& scan, const mrpt::math::TPose2D& pose,
							  const std::vector<size_t>& nodes, double margin, double fraction);

	/** `nodes` split into passes (see kPassGap, kMinPassKeyframes, kMaxPassKeyframes), each
	 * in index order. */
	static std::vector<std::vector<size_t>> passesOf(std::vector<size_t> nodes);

private:
	/** The pass's cloud, in the frame of its first keyframe, and that keyframe's map pose. */
	const std::pair<CReferenceCloud, mrpt::math::TPose2D>& cloudOf(
		const std::vector<size_t>& pass);

	const CPoseGraph& m_map;
	const TKeyframes& m_keyframes;
	TScanMatcherParams m_params;
	std::map<std::vector<size_t>, std::pair<CReferenceCloud, mrpt::math::TPose2D>> m_passes;
};

}  // namespace lrgc
