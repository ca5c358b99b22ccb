/* CPieceJoiner: where does a piece mapped in its own frame join a saved map? (issue 29)
 *
 * A log continuing a saved map is mapped from its first scan as a piece of its own
 * (CMetricMapBuilderLRGC::startPiece). Beside mapping, the paper's global correlation
 * (CGlobalLocalizer: the whole old map, every heading) is tried with the piece's recent patch:
 * its newest keyframes' points (at most patch_keyframes of them, within patch_max_range_m of
 * the newest) in the newest one's frame, when the piece holds 1, 2, 4, ... keyframes, then
 * every quarter of patch_keyframes (CPatchSchedule). A piece that starts on known ground is
 * placed within its first few scans; one that starts elsewhere is placed once the robot
 * reaches known ground, whatever it drove before. The correlation runs on CGlobalSearchWorker's
 * thread and its result is taken at the scan the log fixes (due = submitted + modelled work /
 * search_budget_ms_per_s), so an offline run is deterministic and the mapping thread never
 * waits for a search it could do without. A result is accepted only if it passes the three
 * filters of [PatchCorrelator] (score, ambiguity, variance), as the start of a log is, and if
 * each keyframe of the patch, placed there, matches the map's keyframes around it
 * (CMetricMapBuilderLRGC::pieceJoinProblem; as a localisation's start,
 * CLocalizer::probeMatchesMap): a patch of corridors can pass the filters in a mirror.
 * The old map is copied into the correlation grid at construction: the piece's own keyframes
 * are never searched.
 */
#pragma once

#include <lrgc/localization/GlobalSearchWorker.h>
#include <lrgc/localization/LocalizationParams.h>
#include <lrgc/localization/StartFinder.h>
#include <lrgc/map_builder/CMetricMapBuilderLRGC.h>

#include <optional>
#include <string>

namespace lrgc
{
/** Where the piece joins the map: its keyframe `node` at `nodeInMap`. */
struct TPieceJoin
{
	size_t node = 0;
	mrpt::math::TPose2D nodeInMap{0, 0, 0};         //!< (map <- keyframe node)
	Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();  //!< of nodeInMap [m^2, rad^2], map axes
	double score = 0, ambiguity = 0;                //!< of the accepted correlation
	size_t patchKeyframes = 0;                      //!< keyframes in the accepted patch
};

class CPieceJoiner
{
public:
	/** The old map: node i of `map` at its pose with keyframes[i]'s scan (copied into the
	 * correlation grid). `backgroundSearch` off: searches run on the caller's thread. */
	CPieceJoiner(const CPoseGraph& map, const TKeyframes& keyframes,
				 const TPatchCorrelatorParams& correlator,
				 const TLocalizationParams& localization, bool backgroundSearch = true);

	/** The search in hand ends early, finding nothing, once `stop` is stopped. */
	void setStopToken(const CStopToken& stop) { m_global.setStopToken(stop); }
	/** A live run: service() takes a search's result as soon as it is ready, never waiting
	 * for it (CGlobalSearchWorker::setTakeWhenReady); off by default, so an offline run
	 * takes it at the scan its modelled time fixes. */
	void setResultsWhenReady(bool whenReady) { m_worker.setTakeWhenReady(whenReady); }

	/** After each log entry, `now` its log time [s]: takes the search result due by then (the
	 * join if it passed the filters), then hands the piece's next patch over if one is due
	 * and the worker is free. Requires builder.pieceFirstNode(). */
	std::optional<TPieceJoin> service(const CMetricMapBuilderLRGC& builder, double now);

	size_t attempts() const { return m_attempts; }
	double secondsSpent() const { return m_seconds; }  //!< in correlation, on the worker [s]
	/** Time service() waited for the real worker to keep up with the modelled one [s]. */
	double replayWaitSeconds() const { return m_worker.waitedSeconds(); }
	/** Why the last attempt failed ("score 0.41 < min_score 0.60"), empty before one. */
	const std::string& lastRejection() const { return m_lastRejection; }
	/** Correlations that passed the filters but not the scan check (service()). */
	size_t refusedByScan() const { return m_refusedByScan; }

private:
	std::optional<TPieceJoin> conclude(const TGlobalLocation& location);
	/** Why the patch's keyframes, placed by `join`, do not confirm it; empty if they do. */
	std::string patchProblem(const CMetricMapBuilderLRGC& builder,
							 const TPieceJoin& join) const;

	TLocalizationParams m_params;
	CGlobalLocalizer m_global;
	CGlobalSearchWorker m_worker;
	CPatchSchedule m_schedule;
	/** The patch in the worker and its newest keyframe. */
	std::optional<TPatchRequest> m_inFlight;
	size_t m_inFlightNode = 0;
	double m_logClock = -1e300;  //!< latest log time so far [s]: never backwards
	size_t m_attempts = 0, m_refusedByScan = 0;
	double m_seconds = 0;
	std::string m_lastRejection;
};

}  // namespace lrgc
