/* The run summary's figures and the one-line messages of a run continuing a saved map as a
 * piece of its own (--initial-map: CMetricMapBuilderLRGC::startPiece, CPieceJoiner), shared by
 * the offline app (CSlamApp::continueInitialMap) and the live one (CLiveMapper) so both say
 * the same. The messages carry no prefix: the caller adds its own ("lrgc-slam: ", "live: "). */
#pragma once

#include <lrgc/localization/PieceJoiner.h>
#include <lrgc/map_builder/CMetricMapBuilderLRGC.h>
#include <lrgc_apps/RunOutputs.h>

#include <string>

namespace lrgc::apps
{
struct TSavedMap;

/** Before the first scan: records the map in `run`; "continuing 'M': N keyframes, L links
 * (...); the log is mapped as a piece of its own until global correlation joins it ...". */
std::string continuingMessage(const TSavedMap& map, const CMetricMapBuilderLRGC& builder,
							  TRunSummary& run);

/** The piece was joined: records it in `run` (joined, frame "map", startScans); "the log
 * starts at (x m, y m, phi deg) in the map: joined after ...". */
std::string joinMessage(const TPieceJoin& join, const CPieceJoiner& joiner,
						const CMetricMapBuilderLRGC& builder, TRunSummary& run);

/** --merge, after joinMessage(): "'B' placed in 'A' at (A <- B) = (x m, y m, phi deg) after
 * K of its N keyframes, ... attempts (score, ambiguity)". */
std::string mergeJoinMessage(const TRunSummary& run);

/** The joiner's figures so far into `run`: startAttempts, startSeconds, joinReplayWaitSeconds,
 * lastJoinRejection, and startScans (the scans mapped) while not joined. */
void recordJoinerFigures(const CPieceJoiner& joiner, const CMetricMapBuilderLRGC& builder,
						 TRunSummary& run);

/** The frame the poses of a piece not joined to the map are stated in (startPiece): "the
 * log's own frame (its first scan at (x m, y m, phi deg), its odometry pose)". */
std::string pieceFrame(const CMetricMapBuilderLRGC& builder);

/** After the final optimisation: a piece never joined is kept; sets run.frame and returns
 * "the log was not joined to the map 'M' (...): kept, ...", or empty if there is none. */
std::string keptPieceMessage(const CMetricMapBuilderLRGC& builder, TRunSummary& run);

}  // namespace lrgc::apps
