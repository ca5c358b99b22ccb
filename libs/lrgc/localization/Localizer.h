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
 *     scans from then on (a new CStartFinder) while odometry carries the pose; when it
 *     succeeds (a relocalisation), the scans since the loss get their located poses. A good
 *     tracking match before that ends the loss.
 * The map is never changed. Frames: poses (map <- robot) [m, rad].
 */
#pragma once

#include <lrgc/localization/GlobalLocalizer.h>
#include <lrgc/localization/LocalizationParams.h>
#include <lrgc/localization/StartFinder.h>
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

struct TLocalizerStats
{
	size_t scans = 0;                         //!< laser scans of the laser used
	size_t localizedScans = 0;                //!< scans with a map pose (the trajectory)
	size_t scansBeforeStart = 0;              //!< scans taken before the start was found
	size_t goodMatches = 0, poorMatches = 0;  //!< tracking against the map, once started
	size_t recentMatches = 0;        //!< of the poor ones, placed by the log's recent scans
	size_t lostEvents = 0;           //!< lost_after poor matches in a row
	size_t relocalizations = 0;      //!< lost, then found again by global localisation
	size_t recoveredByTracking = 0;  //!< lost, then a good tracking match came first
	size_t globalAttempts = 0;       //!< global correlations (start and relocalisations)
	double globalSeconds = 0;        //!< their total time [s]
	bool started = false;            //!< the start was found
	std::string lastRejection;       //!< of the last failed global attempt
};

class CLocalizer : public mrpt::system::COutputLogger
{
public:
	/** The map: node i of `map` at its pose with keyframes[i]'s scan (copied). */
	CLocalizer(const CPoseGraph& map, const TKeyframes& keyframes, const TLRGCParams& params,
			   const TLocalizationParams& localization);
	~CLocalizer() override;

	/** Odometry (CObservationOdometry) or a 2D laser scan; other kinds are ignored. */
	void processObservation(const mrpt::obs::CObservation::Ptr& obs);
	void processActionObservation(mrpt::obs::CActionCollection& action,
								  mrpt::obs::CSensoryFrame& observations);

	/** Global localisation (the start, relocalisations) and the wide rotational search end
	 * early, finding nothing, once `stop` is stopped (StopToken.h). */
	void setStopToken(const CStopToken& stop);

	/** One pose per localised scan, in the order of the scans. */
	const TTrajectory& trajectory() const { return m_trajectory; }
	const TLocalizerStats& stats() const;
	/** Timestamp of the last scan processed (default-constructed before the first). */
	mrpt::Clock::time_point lastScanTimestamp() const { return m_lastScanTime; }
	/** The laser used (first seen). */
	const std::string& laserLabel() const { return m_laserLabel; }

private:
	void processScan(const mrpt::obs::CObservation2DRangeScan::Ptr& laser);
	void feedFinder(const mrpt::obs::CObservation2DRangeScan::Ptr& laser);
	void adoptFinderPoses(const TStartFound& found);
	bool track(const TScan2D& scan, mrpt::Clock::time_point t);
	/** The reference cloud of the map keyframes near `pose`; false if there are none. */
	bool referenceNear(const mrpt::math::TPose2D& pose);
	/** The prior matched against the recent scans; nullopt if that fails too. */
	std::optional<mrpt::math::TPose2D> matchRecent(const TScan2D& scan,
												   const mrpt::math::TPose2D& prior) const;
	void keepRecent(const TScan2D& scan, const mrpt::math::TPose2D& pose);

	CPoseGraph m_map;
	TKeyframes m_keyframes;
	TLRGCParams m_params;
	TLocalizationParams m_lp;
	CGlobalLocalizer m_global;
	CScanMatcher m_matcher;
	CStopToken m_stop;
	std::unique_ptr<CMotionPredictor> m_predictor;
	/** Searching for the start or relocalising: the probe, fed the scans since then. */
	std::unique_ptr<CStartFinder> m_finder;
	size_t m_finderFirstIndex = 0;  //!< index in m_trajectory of the finder's first scan

	TTrajectory m_trajectory;
	mrpt::math::TPose2D m_pose{0, 0, 0};  //!< of the last scan
	Eigen::Matrix3d m_driftCov =
		Eigen::Matrix3d::Zero();  //!< since the last good match, map axes
	size_t m_poorInARow = 0;
	std::vector<size_t> m_refNodes;  //!< keyframes of the current reference cloud
	CReferenceCloud m_ref;
	mrpt::math::TPose2D m_refInMap{0, 0, 0};
	/** The log's own recent scans with their map poses, for matchRecent(). */
	std::deque<std::pair<TScan2D, mrpt::math::TPose2D>> m_recent;
	std::string m_laserLabel;
	mrpt::Clock::time_point m_lastScanTime{};
	mutable TLocalizerStats m_stats;
	double m_finderSecondsBefore = 0;  //!< correlation time of finders already finished
	size_t m_finderAttemptsBefore = 0;
};

}  // namespace lrgc
