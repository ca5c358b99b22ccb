/* Loop recall judged by ground-truth relations alone (definition in relation_truth.h). */
#include "lrgc_apps/eval/relation_truth.h"

#include <lrgc/common/se2.h>

#include <algorithm>
#include <cmath>
#include <deque>

namespace lrgc::apps::eval
{
namespace
{
/** Index of the timestamp in sorted `stamps` within tol of t, or nothing. */
std::optional<std::size_t> findStamp(const std::vector<double>& stamps, double t, double tol)
{
	const auto it = std::lower_bound(stamps.begin(), stamps.end(), t - tol);
	if (it == stamps.end() || *it > t + tol) return std::nullopt;
	return std::size_t(it - stamps.begin());
}

/** The relation timestamps, sorted, those within tol of the previous one merged. */
std::vector<double> relationStamps(const std::vector<TRelation>& relations, double tol)
{
	std::vector<double> all;
	for (const auto& r : relations) all.push_back(r.t1), all.push_back(r.t2);
	std::sort(all.begin(), all.end());
	std::vector<double> out;
	for (const double t : all)
		if (out.empty() || t - out.back() > tol) out.push_back(t);
	return out;
}
}  // namespace

CRelationTruth::CRelationTruth(const std::vector<TRelation>& relations,
							   const std::vector<TRecallKeyframe>& keyframes,
							   const TRelationTruthParams& p)
	: p_(p)
{
	const std::vector<double> stamps = relationStamps(relations, p.tolerance_s);
	edges_.resize(stamps.size());
	for (const auto& r : relations)
	{
		const std::size_t a = *findStamp(stamps, r.t1, p.tolerance_s);
		const std::size_t b = *findStamp(stamps, r.t2, p.tolerance_s);
		if (a == b) continue;
		edges_[a].push_back({b, r.motion});
		edges_[b].push_back({a, lrgc::inverse(r.motion)});
	}
	anchor_.resize(keyframes.size());
	isBridged_.assign(keyframes.size(), false);
	for (std::size_t i = 0; i < keyframes.size(); ++i)
	{
		keyframeTime_.push_back(keyframes[i].t);
		if (const auto n = findStamp(stamps, keyframes[i].t, p.tolerance_s))
			anchor_[i] = std::make_pair(*n, mrpt::math::TPose2D(0, 0, 0)), ++own_;
	}
	// Keyframes no relation names: the anchor of the nearest in time that has its own.
	const auto own = anchor_;
	for (std::size_t i = 0; i < keyframes.size(); ++i)
	{
		if (own[i]) continue;
		std::optional<std::size_t> best;
		for (std::size_t j = 0; j < keyframes.size(); ++j)
			if (own[j] && std::abs(keyframes[j].t - keyframes[i].t) <= p.bridge_s &&
				(!best || std::abs(keyframes[j].t - keyframes[i].t) <
							  std::abs(keyframes[*best].t - keyframes[i].t)))
				best = j;
		if (!best) continue;
		anchor_[i] =
			std::make_pair(own[*best]->first,
						   lrgc::between(keyframes[i].reference, keyframes[*best].reference));
		isBridged_[i] = true;
		++bridged_;
	}
	for (std::size_t i = 0; i < keyframes.size(); ++i)
		if (anchor_[i]) keyframesAt_[anchor_[i]->first].push_back(i);
}

const std::map<std::size_t, CRelationTruth::TReached>& CRelationTruth::reach(
	std::size_t node) const
{
	const auto cached = reachCache_.find(node);
	if (cached != reachCache_.end()) return cached->second;
	// Breadth first: each node first reached by a path of fewest relations.
	std::map<std::size_t, TReached> reached{{node, {mrpt::math::TPose2D(0, 0, 0), 0}}};
	std::deque<std::size_t> queue{node};
	while (!queue.empty())
	{
		const TReached at = reached.at(queue.front());
		const std::size_t n = queue.front();
		queue.pop_front();
		if (at.relations == p_.maxHops) continue;
		for (const auto& e : edges_[n])
			if (reached
					.emplace(e.to, TReached{lrgc::compose(at.pose, e.motion), at.relations + 1})
					.second)
				queue.push_back(e.to);
	}
	return reachCache_.emplace(node, std::move(reached)).first->second;
}

std::optional<mrpt::math::TPose2D> CRelationTruth::between(std::size_t from,
														   std::size_t to) const
{
	if (!anchor_.at(from) || !anchor_.at(to)) return std::nullopt;
	const auto& [fromNode, fromBridge] = *anchor_[from];
	const auto& [toNode, toBridge] = *anchor_[to];
	const auto& reached = reach(fromNode);
	const auto it = reached.find(toNode);
	if (it == reached.end()) return std::nullopt;
	// (from <- to) = (from <- its anchor) (+) P(anchor -> anchor') (+) (to <- anchor')^-1
	return lrgc::compose(lrgc::compose(fromBridge, it->second.pose), lrgc::inverse(toBridge));
}

std::size_t CRelationTruth::relationsBetween(std::size_t from, std::size_t to) const
{
	if (!between(from, to)) return 0;
	return reach(anchor_[from]->first).at(anchor_[to]->first).relations;
}

bool CRelationTruth::isRevisit(std::size_t i, double gap_s, double near_m) const
{
	if (!anchor_.at(i)) return false;
	for (const auto& [node, reached] : reach(anchor_[i]->first))
	{
		const auto at = keyframesAt_.find(node);
		if (at == keyframesAt_.end()) continue;
		for (const std::size_t j : at->second)
		{
			if (keyframeTime_[i] - keyframeTime_[j] < gap_s) continue;
			const auto d = between(i, j);
			if (d && lrgc::translationNorm(*d) < near_m) return true;
		}
	}
	return false;
}

TLoopRecall evaluateLoopRecall(const lrgc::CPoseGraph& graph,
							   const std::vector<TRecallKeyframe>& keyframes,
							   const CRelationTruth& truth, const TLoopRecallParams& p)
{
	TRecallJudge judge;
	judge.isRevisit = [&](std::size_t i)
	{ return truth.isRevisit(i, p.revisitGap_s, p.revisitNear_m); };
	judge.step_m = [&](std::size_t i)
	{
		const auto d = truth.between(i - 1, i);
		return lrgc::translationNorm(
			d ? *d : lrgc::between(keyframes[i - 1].reference, keyframes[i].reference));
	};
	judge.between = [&](std::size_t from, std::size_t to)
	{
		const auto d = truth.between(from, to);
		if (!d) return std::optional<TRecallJudge::TTruth>();
		const bool bridged = truth.bridged(from) || truth.bridged(to);
		return std::optional<TRecallJudge::TTruth>(
			{*d, !bridged, bridged, truth.relationsBetween(from, to)});
	};
	return evaluateLoopRecall(graph, keyframes, judge, p);
}

}  // namespace lrgc::apps::eval
