/* Loop recall's truth from ground-truth relations alone (issue 28): no reference trajectory,
 * so the judge of a sparse run does not move with the build that maps the dense log.
 *
 * The relations (Kuemmerle et al.: t1 t2 and the true motion (t1 <- t2)) form a graph over
 * their timestamps; most join consecutive scans a few tenths of a metre apart, the rest join
 * a place to its revisit minutes later (Intel 1210 over 60 s apart, ACES 88, MIT-CSAIL 101,
 * Killian 964). The true pose of timestamp b in the frame of a is the composition of the
 * relations along a path of fewest relations, at most `maxHops`:
 *     P(a -> b) = M(a, n1) (+) M(n1, n2) (+) ... (+) M(nk, b),   M(n, m) = (n <- m)
 * (a relation used backwards contributes its inverse), as bench/make-sparse-log moves the
 * relations onto kept scans. Each relation has a small error of its own, and a path of k of
 * them drifts like a random walk of k steps, so the hop limit bounds the judge's own error
 * (moved relations composed of 2-4 that join the same pair of scans disagree in heading by a
 * median 0.3-0.6 deg, at most 2.5 deg: doc/generalisation.md), and a link's position
 * tolerance grows with the path (TLoopRecallParams::maxXYPerRelation_m).
 *
 * A keyframe is anchored at the relation timestamp equal to its scan's time (within
 * `tolerance_s`). One whose scan no relation names (bench/make-sparse-log keeps a scan the
 * relations do not name where they leave a gap: Intel 124 of 749 keyframes, MIT-CSAIL 8 of
 * 385) borrows the anchor of the keyframe nearest in time that has one, within `bridge_s`,
 * bridged by the map's own poses of the two: one scan step (~1 m), where the map is right to
 * a few centimetres, a tenth of the 0.3 m a loop link may be off. Without either, or without
 * a path, the truth is unknown and the link is not judged.
 */
#pragma once

#include <lrgc_apps/eval/loop_recall.h>
#include <lrgc_apps/eval/relation_metric.h>
#include <mrpt/math/TPose2D.h>

#include <cstddef>
#include <map>
#include <optional>
#include <vector>

namespace lrgc::apps::eval
{
struct TRelationTruthParams
{
	std::size_t maxHops = 16;   //!< relations on a path at most
	double bridge_s = 10;       //!< [s] a keyframe without a relation borrows one this near
	double tolerance_s = 1e-5;  //!< [s] a scan and a relation timestamp this close are one
};

class CRelationTruth
{
public:
	/** `keyframes[i].t`: the scan times; `keyframes[i].reference`: the map's own poses (used
	 * only for the bridges above). */
	CRelationTruth(const std::vector<TRelation>& relations,
				   const std::vector<TRecallKeyframe>& keyframes,
				   const TRelationTruthParams& p = {});

	/** The true (from <- to) of two keyframes, or nothing (no anchor or no path). */
	std::optional<mrpt::math::TPose2D> between(std::size_t from, std::size_t to) const;
	/** How many relations the path of between(from, to) composes (0: no path, or one relation
	 * timestamp anchors both): the judge's own error grows with it (each relation of a sparse
	 * log is itself a chain, moved onto kept scans by bench/make-sparse-log). */
	std::size_t relationsBetween(std::size_t from, std::size_t to) const;
	/** Is keyframe i within near_m (by between) of a keyframe at least gap_s older? */
	bool isRevisit(std::size_t i, double gap_s, double near_m) const;
	/** Is keyframe i's anchor borrowed (bridged by the map)? */
	bool bridged(std::size_t i) const { return isBridged_.at(i); }
	/** Keyframes with an anchor of their own, and bridged ones. */
	std::size_t ownAnchors() const { return own_; }
	std::size_t bridgedAnchors() const { return bridged_; }

private:
	struct TEdge
	{
		std::size_t to;
		mrpt::math::TPose2D motion;  //!< (this node <- to)
	};
	/** A node reached from another: P(from -> it), by a path of `relations` relations. */
	struct TReached
	{
		mrpt::math::TPose2D pose;
		std::size_t relations;
	};
	/** Every node m within maxHops relations of `node`, by its path of fewest relations. */
	const std::map<std::size_t, TReached>& reach(std::size_t node) const;

	TRelationTruthParams p_;
	std::vector<double> keyframeTime_;
	std::vector<std::vector<TEdge>> edges_;  //!< per relation timestamp
	/** Per keyframe: its anchor node and (keyframe <- anchor) by the map (identity if own). */
	std::vector<std::optional<std::pair<std::size_t, mrpt::math::TPose2D>>> anchor_;
	std::vector<bool> isBridged_;
	std::map<std::size_t, std::vector<std::size_t>> keyframesAt_;  //!< anchor node -> keyframes
	mutable std::map<std::size_t, std::map<std::size_t, TReached>> reachCache_;
	std::size_t own_ = 0, bridged_ = 0;
};

/** Recall and false closures of `graph` (node i = keyframes[i]) judged by `truth` alone
 * (loop_recall.h's definitions, with distances and poses by truth.between): a keyframe is a
 * revisit if truth puts it within revisitNear_m of one revisitGap_s older; the path of a place
 * sums truth.between of consecutive keyframes (the map's where it is unknown); a link whose
 * truth is unknown is counted in notJudged, neither agreeing nor false. */
TLoopRecall evaluateLoopRecall(const lrgc::CPoseGraph& graph,
							   const std::vector<TRecallKeyframe>& keyframes,
							   const CRelationTruth& truth, const TLoopRecallParams& p = {});

}  // namespace lrgc::apps::eval
