/* The reports of a run continuing a saved map as a piece (see PieceReports.h). */
#include "PieceReports.h"

#include "lrgc_apps/SavedMap.h"

#include <mrpt/core/bits_math.h>
#include <mrpt/core/format.h>

namespace lrgc::apps
{
std::string pieceFrame(const CMetricMapBuilderLRGC& builder)
{
	const auto trajectory = builder.trajectory();
	if (trajectory.empty()) return "the log's own frame";
	const mrpt::math::TPose2D& first = trajectory.front().robotInMap;
	return mrpt::format(
		"the log's own frame (its first scan at (%.2f m, %.2f m, %.1f deg), its odometry pose)",
		first.x, first.y, mrpt::RAD2DEG(first.phi));
}

std::string continuingMessage(const TSavedMap& map, const CMetricMapBuilderLRGC& builder,
							  TRunSummary& run)
{
	run.initialMap = map.path;
	run.initialMapKeyframes = builder.graph().numNodes();
	return mrpt::format(
		"continuing '%s': %zu keyframes, %zu links (%s); the log is mapped as a piece of its "
		"own until global correlation joins it to the map",
		map.path.c_str(), builder.graph().numNodes(), builder.graph().numLinks(),
		map.graph ? "the saved graph" : "linked anew from the keyframes' poses");
}

std::string joinMessage(const TPieceJoin& join, const CPieceJoiner& joiner,
						const CMetricMapBuilderLRGC& builder, TRunSummary& run)
{
	run.joined = true;
	run.frame = "map";
	run.joinScore = join.score;
	run.joinAmbiguity = join.ambiguity;
	run.startScans = builder.stats().scans;
	const mrpt::math::TPose2D start = builder.trajectory().front().robotInMap;
	return mrpt::format(
		"the log starts at (%.2f m, %.2f m, %.1f deg) in the map: joined after %zu scans, %zu "
		"attempts, %.1f s (score %.2f, ambiguity %.2f, patch of %zu keyframes)",
		start.x, start.y, mrpt::RAD2DEG(start.phi), run.startScans, joiner.attempts(),
		joiner.secondsSpent(), join.score, join.ambiguity, join.patchKeyframes);
}

std::string mergeJoinMessage(const TRunSummary& run)
{
	const mrpt::math::TPose2D& t = run.pieceInMap;
	return mrpt::format(
		"'%s' placed in '%s' at (A <- B) = (%.3f m, %.3f m, %.2f deg) after %zu of its %zu "
		"keyframes (score %.2f, ambiguity %.2f)",
		run.mergedMap.c_str(), run.initialMap.c_str(), t.x, t.y, mrpt::RAD2DEG(t.phi),
		run.startScans, run.mergedMapKeyframes, run.joinScore, run.joinAmbiguity);
}

void recordJoinerFigures(const CPieceJoiner& joiner, const CMetricMapBuilderLRGC& builder,
						 TRunSummary& run)
{
	run.startAttempts = joiner.attempts();
	run.joinsRefusedByScan = joiner.refusedByScan();
	run.startSeconds = joiner.secondsSpent();
	run.joinReplayWaitSeconds = joiner.replayWaitSeconds();
	run.lastJoinRejection = joiner.lastRejection();
	if (!run.joined) run.startScans = builder.stats().scans;
}

std::string keptPieceMessage(const CMetricMapBuilderLRGC& builder, TRunSummary& run)
{
	if (run.joined || !builder.pieceFirstNode() || builder.stats().scans == 0) return {};
	run.frame = pieceFrame(builder);
	return mrpt::format(
		"the log was not joined to the map '%s' (%zu global correlation attempts, last: %s): "
		"kept, its keyframes %zu..%zu and trajectory.tum stated in %s",
		run.initialMap.c_str(), run.startAttempts,
		run.lastJoinRejection.empty() ? "none" : run.lastJoinRejection.c_str(),
		*builder.pieceFirstNode(), builder.graph().numNodes() - 1, run.frame.c_str());
}

}  // namespace lrgc::apps
