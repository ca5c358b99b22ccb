/* CLocalizer: localisation only. Tracks a robot on a saved map without changing the map.
 *
 *  1. Start: the pose in the map is unknown; CStartFinder maps the first scans on their own
 *     and correlates them against the whole map (global correlation, paper section 2.3)
 *     until a patch passes the filters; those scans then get their map poses.
 *  2. Tracking: each scan's pose is predicted from odometry (CMotionPredictor) and matched
 *     (CScanMatcher) against a reference cloud of the map keyframes within track_radius_m of
 *     the prediction (the nearest track_max_keyframes, placed at their map poses). A match is
 *     good if min_inlier_fraction of the scan matched and it agrees with the prediction within
 *     gate_chi2 under the prediction's covariance (grown while matches are poor) plus the
 *     match's and the map's own noise floor ([LoopCloser] link_floor_*). Otherwise the scan
 *     is matched against the log's own recent scans (the last [LocalRegistration]
 *     window_size scans kept [MapBuilder] keyframe_distance_m apart), as local registration
 *     does: where the map has no walls the new scans see (a room mapped from its door, a
 *     moved cupboard) the pose stays locally consistent instead of following raw odometry,
 *     and the map takes over again when it matches. Only if both fail the prediction is kept.
 *  3. Lost: after lost_after poor matches in a row, global localisation runs again on the
 *     scans from then on (a new CStartFinder) while tracking carries the pose; when it
 *     succeeds (a relocalisation), the scans since the loss get their located poses. A good
 *     tracking match before that ends the loss. Where to look: within 3 sigma of the
 *     carried pose (its drift covariance, at least kMinSearchHalfXY and kMinSearchHalfTheta),
 *     and the whole map at once if the robot was kidnapped: kidnap_after scans in a row that
 *     contradict the map where the robot is thought to be (kContradictionFraction: walls
 *     where the map saw free space), with patches of at most kKidnapPatchKeyframes.
 * Global correlations never run on the tracking thread (CGlobalSearchWorker): the start and
 * every relocalisation are searched beside it and applied at a scan fixed by the log.
 * The map is never changed. Frames: poses (map <- robot) [m, rad].
 */
#pragma once

#include <lrgc/localization/StartFinder.h>
#include <lrgc/localization/GlobalLocalizer.h>
#include <lrgc/localization/GlobalSearchWorker.h>
#include <lrgc/localization/LocalizationParams.h>
#include <lrgc/localization/ViewContradiction.h>
#include <lrgc/map_builder/MapBuilderParams.h>
#include <lrgc/map_builder/Trajectory.h>
#include <lrgc/scan_matching/ReferenceCloud.h>
#include <lrgc/scan_matching/ScanMatcher.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/system/COutputLogger.h>

#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace lrgc
{
class CMotionPredictor;

/** Something a navigation stack needs to hear of, at a scan of the log. */
struct TLocalizationEvent
{
	enum class Kind
	{
		Started,              //!< the start was found
		Lost,                 //!< lost_after poor matches in a row
		Kidnapped,            //!< kidnap_after scans in a row contradicting the map
		Relocalized,          //!< lost, then placed by global localisation
		RecoveredByTracking,  //!< lost, then a good tracking match came first
	};
	Kind kind = Kind::Lost;
	double stamp = 0;                   //!< of the scan [s]
	mrpt::math::TPose2D pose{0, 0, 0};  //!< of that scan (map <- robot), after the event
	double jump_m = 0;                  //!< Relocalized: how far the pose moved [m]
	double window_m = 0;  //!< Started, Relocalized: half width of the search window [m]
	/** "started", "lost", "kidnapped", "relocalized", "recovered_by_tracking". */
	const char* name() const;
};

struct TLocalizerStats
{
	size_t scans = 0;                         //!< laser scans of the laser used
	size_t localizedScans = 0;                //!< scans with a map pose (the trajectory)
	size_t scansBeforeStart = 0;              //!< scans taken before the start was found
	size_t goodMatches = 0, poorMatches = 0;  //!< tracking against the map, once started
	size_t recentMatches = 0;        //!< of the poor ones, placed by the log's recent scans
	size_t lostEvents = 0;           //!< lost_after poor matches in a row
	size_t kidnapEvents = 0;         //!< kidnap_after scans in a row contradicting the map
	size_t relocalizations = 0;      //!< lost, then found again by global localisation
	size_t recoveredByTracking = 0;  //!< lost, then a good tracking match came first
	size_t globalAttempts = 0;       //!< global correlations (start and relocalisations)
	/** Of the correlations that passed the filters, those refused because a keyframe of the
	 * patch, placed there, failed tracking's match against the map
	 * (CLocalizer::probeMatchesMap). */
	size_t globalRefusedByScan = 0;
	double globalSeconds = 0;          //!< their total time [s], on the search thread
	double globalModelledSeconds = 0;  //!< their modelled time (TGlobalLocation) [s]
	/** Time the tracking thread waited for the search thread to keep up with the modelled
	 * one (replaying a log faster than it was recorded) [s], in all and the longest. */
	double replayWaitSeconds = 0, replayWaitMaxSeconds = 0;
	/** Scans processed while a global search was in hand, and searches the tracking thread
	 * ran itself (0 unless built with backgroundSearch off). */
	size_t scansDuringSearches = 0, searchesOnTrackingThread = 0;
	std::vector<TLocalizationEvent> events;
	bool started = false;       //!< the start was found
	std::string lastRejection;  //!< of the last failed global attempt
};

class CLocalizer : public mrpt::system::COutputLogger
{
public:
	/** [m], [rad] Smallest half window of a relocalisation search (a carried pose whose
	 * covariance says it is right within centimetres, yet tracking fails, is wrong by more). */
	static constexpr double kMinSearchHalfXY = 1.0, kMinSearchHalfTheta = 0.35;
	/** A scan contradicts the map when it does not match it and, at the predicted pose, at
	 * least this fraction of its points (or of the map's) lie more than kContradictionMargin
	 * [m] inside space the other side's beams crossed (CReferenceCloud::freeSpaceViolation).
	 * Measured on Intel's second half: 0.38-0.51 for 10 scans after a 25 m kidnap; rooms the
	 * map saw only from their doors 0-0.03. The joined cloud first, then each pass of its
	 * keyframes on its own (CViewContradiction): a scan that agrees with one pass is where it
	 * is thought to be, in a place that changed between the map's passes. */
	static constexpr double kContradictionFraction = 0.3, kContradictionMargin = 0.2;
	/** Largest patch of a kidnap's whole-map search [keyframes]; past it the attempts back
	 * off (CStartFinder). Intel: a 25 m kidnap was found with 1 keyframe; whole-map attempts
	 * with 16-32 keyframes cost 6-10 s each, and where they kept failing (a stretch the first
	 * half's map barely covers) they cost 40 s of modelled work. */
	static constexpr size_t kKidnapPatchKeyframes = 8;
	/** [m] A match the joined reference's free-space check refuses stands (matchReference)
	 * only if it fits tightly: at least kKeepInlierFraction of the scan matched, with an rms
	 * residual under this. */
	static constexpr double kChangedPlaceRms_m = 0.03;
	/** The tracking reference is kept (stillCovers) only while the last scan matched it well:
	 * a good match with at least this fraction of its points matched. Where the map is
	 * partial (Intel's second half on the first half's map: 30 % poor matches) the reference
	 * is then built as before; keeping it there regardless put that run's relation error at
	 * 0.10 m (0.0334 at share 0.75). */
	static constexpr double kKeepInlierFraction = 0.8;
	/** Whether the reference built from the keyframes `current` still serves a pose whose
	 * near keyframes are `near` (both sorted; `nearest` the nearest of them): it holds
	 * `nearest` and at least share * |near| of `near` ([Localization] track_keep_share). */
	static bool stillCovers(const std::vector<size_t>& current, const std::vector<size_t>& near,
							size_t nearest, double share);

	/** Whether a tracking match whose free-space violation against the joined reference
	 * (m.freeSpaceViolation) is above `limit` must be refused (matchReference): unless it fits
	 * tightly (kKeepInlierFraction, kChangedPlaceRms_m) and agrees with some pass of `nodes` on
	 * its own (views.contradictsEveryPass at `poseInMap`, `margin` [m]). Below the limit:
	 * never. */
	static bool refusedByFreeSpace(const TScanMatch& m, double limit, CViewContradiction& views,
								   const TScan2D& scan, const mrpt::math::TPose2D& poseInMap,
								   const std::vector<size_t>& nodes, double margin);

	/** The map: node i of `map` at its pose with keyframes[i]'s scan (copied).
	 * `backgroundSearch` off: global searches run on the caller's thread (same results). */
	CLocalizer(const CPoseGraph& map, const TKeyframes& keyframes, const TLRGCParams& params,
			   const TLocalizationParams& localization, bool backgroundSearch = true);
	~CLocalizer() override;

	/** Odometry (CObservationOdometry) or a 2D laser scan; other kinds are ignored. */
	void processObservation(const mrpt::obs::CObservation::Ptr& obs);
	void processActionObservation(mrpt::obs::CActionCollection& action,
								  mrpt::obs::CSensoryFrame& observations);

	/** Global localisation (the start, relocalisations) and the wide rotational search end
	 * early, finding nothing, once `stop` is stopped (StopToken.h). */
	void setStopToken(const CStopToken& stop);

	/** Live use: a global search's result is applied at the first scan after it ended, never
	 * waiting for the search (CGlobalSearchWorker::setTakeWhenReady); off by default, so
	 * that a log replays the same on any machine. */
	void setResultsWhenReady(bool whenReady) { m_worker.setTakeWhenReady(whenReady); }

	/** One pose per localised scan, in the order of the scans, but for those already moved
	 * out by takeSettledPoses(). */
	const TTrajectory& trajectory() const { return m_trajectory; }
	/** Moves out the poses no later scan can change (all of them, but while a relocalisation
	 * search runs, those since it began: a success rewrites them). A caller that writes them
	 * out as it goes keeps the localiser's memory flat however long it runs. */
	TTrajectory takeSettledPoses();
	const TLocalizerStats& stats() const;
	/** Timestamp of the last scan processed (default-constructed before the first). */
	mrpt::Clock::time_point lastScanTimestamp() const { return m_lastScanTime; }
	/** Replay wait (see TLocalizerStats) during the last processed entry [s]. */
	double lastReplayWaitSeconds() const { return m_lastWait; }
	/** The laser used (first seen). */
	const std::string& laserLabel() const { return m_laserLabel; }

private:
	void processScan(const mrpt::obs::CObservation2DRangeScan::Ptr& laser);
	/** Tracking one scan, then the loss bookkeeping. */
	void trackAndWatch(const TScan2D& scan, mrpt::Clock::time_point t);
	void startSearch(bool wholeMap);
	void dropSearch();
	/** Applies the search result due at `stamp`, then submits the next attempt if due. */
	void serviceSearch(double stamp);
	void applySearchResult(const TGlobalLocation& location, double stamp);
	TSearchArea searchArea(const mrpt::math::TPose2D& newestInProbe) const;
	void adoptFinderPoses(const TStartFound& found);
	/** A global correlation's pose checked scan by scan: each keyframe of the accepted patch
	 * (the probe's newest found.patchKeyframes), placed where `found` puts it, must make a
	 * good tracking match against the map there. */
	bool probeMatchesMap(const TStartFound& found);
	void record(TLocalizationEvent::Kind kind, double stamp, double jump = 0,
				double window = 0);
	/** Matches the scan (map, else recent scans); true if the map match is good.
	 * `contradicted`: see kContradictionFraction. */
	bool track(const TScan2D& scan, mrpt::Clock::time_point t, bool& contradicted);
	/** The reference cloud of the map keyframes near `pose`; false if there are none.
	 * `mayKeep`: the current one is kept while it still covers them (stillCovers). */
	bool referenceNear(const mrpt::math::TPose2D& pose, bool mayKeep);
	/** The scan matched against the tracking reference (m_ref) from `guess`. Its free-space
	 * check is asked as a kidnap's is: a match the joined reference refuses (more than
	 * [LocalRegistration] max_free_space_violation of the scan where some pass's beams went
	 * through) stands unless it contradicts each pass of the reference's keyframes on its own
	 * (CViewContradiction): a place changed between the map's passes is not a wrong match. */
	std::optional<TScanMatch> matchReference(const TScan2D& scan,
											 const mrpt::math::TPose2D& guess);
	/** A tracking match is good: enough inliers and within gate_chi2 of the prior. */
	bool isGoodMatch(const std::optional<TScanMatch>& m, const mrpt::math::TPose2D& guess,
					 const Eigen::Matrix3d& priorCov) const;
	/** The prior matched against the recent scans; nullopt if that fails too. */
	std::optional<mrpt::math::TPose2D> matchRecent(const TScan2D& scan,
												   const mrpt::math::TPose2D& prior);
	void keepRecent(const TScan2D& scan, const mrpt::math::TPose2D& pose);

	CPoseGraph m_map;
	TKeyframes m_keyframes;
	TLRGCParams m_params;
	TLocalizationParams m_lp;
	CViewContradiction m_views;  //!< of m_map and m_keyframes (declared after them)
	CGlobalLocalizer m_global;
	CScanMatcher m_matcher;
	CScanMatcher m_trackMatcher;  //!< m_matcher without its free-space check: matchReference
	CStopToken m_stop;
	std::unique_ptr<CMotionPredictor> m_predictor;
	/** Searching for the start or relocalising: the probe, fed the scans since then. */
	std::unique_ptr<CStartFinder> m_finder;
	size_t m_finderFirstIndex = 0;  //!< index in m_trajectory of the finder's first scan
	bool m_searchWholeMap = true;   //!< the finder's attempts search the whole map
	CGlobalSearchWorker m_worker;
	/** The attempt in the worker: its patch, its finder's generation and window. */
	std::optional<TPatchRequest> m_inFlight;
	size_t m_inFlightGeneration = 0, m_generation = 0;
	double m_inFlightWindow = 0;
	double m_lastWait = 0;

	TTrajectory m_trajectory;             //!< poses not yet taken by takeSettledPoses()
	size_t m_posesTaken = 0;              //!< by takeSettledPoses()
	mrpt::math::TPose2D m_pose{0, 0, 0};  //!< of the last scan
	Eigen::Matrix3d m_driftCov =
		Eigen::Matrix3d::Zero();  //!< since the last good match, map axes
	size_t m_poorInARow = 0;
	size_t m_contradictedInARow = 0;  //!< scans contradicting the map (track())
	std::vector<size_t> m_refNodes;   //!< keyframes of the current reference cloud
	bool m_lastMapGood = false;       //!< the last scan matched the reference well (keep it)
	bool m_refExact = false;          //!< m_refNodes are the keyframes near the last pose asked
	CReferenceCloud m_ref;
	mrpt::math::TPose2D m_refInMap{0, 0, 0};
	/** The log's own recent scans with their map poses, for matchRecent(). */
	std::deque<std::pair<TScan2D, mrpt::math::TPose2D>> m_recent;
	std::optional<CReferenceCloud> m_recentCloud;  //!< of m_recent, in its newest's frame
	std::string m_laserLabel;
	mrpt::Clock::time_point m_lastScanTime{};
	double m_logClock = -1e300;  //!< latest scan stamp so far [s] (the search schedule's clock)
	mutable TLocalizerStats m_stats;
};

}  // namespace lrgc
