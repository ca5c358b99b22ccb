/* CMetricMapBuilderLRGC: the LRGC map builder (Gutmann & Konolige 2000, section 2.4, fig. 6)
 * as an MRPT map builder, a drop-in for mrpt::slam::CMetricMapBuilderICP.
 *
 * The map is a graph (CPoseGraph): nodes are keyframe poses with their scans, links come
 * from odometry, scan matching and correlation. Each scan goes through a short story:
 *   1. predict its pose from odometry (or constant velocity without odometry);
 *   2. register it locally against the last K keyframes (CLocalRegistration);
 *   3. if it travelled far enough, add it to the graph as a keyframe, linked to the window,
 *      and re-estimate the window's poses (Lu & Milios over the last K only); on ground the
 *      map already has, anchor it at the keyframe there instead (CKeyframeReuse);
 *   4. look for a loop and close it (when the loop-closure stage is enabled): CLoopClosing
 *      hands the keyframe to a worker thread and applies its result (new links, corrected
 *      poses) some keyframes later, the poses added meanwhile carried along by the correction.
 * Every scan, keyframe or not, is kept in the trajectory relative to its keyframe, so
 * optimisations move it along. The map is updated with every scan (anytime).
 *
 * Threads: as MRPT expects of a CMetricMapBuilder, changes to the map happen inside its
 * critical section (critZoneChangingMap), and the getters that copy something out
 * (getCurrentPoseEstimation, getCurrentlyBuiltMap(Size), getCurrentlyBuiltMetricMap,
 * saveCurrentEstimationToImage, trajectory, buildOccupancyGrid, gridKeyframes, statsCopy,
 * loopCloserStats, lastScanTimestamp) take it too, so another thread may call them while
 * mapping goes on. The getters returning references (graph, keyframes, stats, lasers, params)
 * are for the mapping thread, or for any thread once mapping has stopped.
 */
#pragma once

#include <lrgc/map_builder/LaserSelector.h>
#include <lrgc/common/StopToken.h>
#include <lrgc/loop_closing/LoopCloserStats.h>
#include <lrgc/map_builder/GridKeyframes.h>
#include <lrgc/map_builder/MapBuilderParams.h>
#include <lrgc/map_builder/Trajectory.h>
#include <lrgc/scan_matching/DeferredCovariance.h>
#include <lrgc/scan_matching/Keyframe.h>
#include <lrgc/scan_matching/RangeDenoiser.h>
#include <lrgc/pose_graph/PoseGraph.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/slam/CMetricMapBuilder.h>

#include <chrono>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

namespace mrpt::maps
{
class COccupancyGridMap2D;  // buildOccupancyGrid's result: include its header to use it
}

namespace lrgc
{
// The stages are the builder's internals: users see its products (graph, keyframes,
// trajectory) and its parameters, not the classes that make them.
class CIncrementalGrid;
class CMotionPredictor;
class CLocalRegistration;
class CSweepEstimator;
class CLoopClosing;
class CKeyframeReuse;
class CKeyframeRematcher;
struct TReusedKeyframe;
struct TRegistration;
struct TLoopUpdate;
struct TMotionPrediction;
struct TLoopClosingTestAccess;

/** Counters of a run, for stats.json and logs. */
struct TMapBuilderStats
{
	size_t scans = 0;  //!< laser scans placed in the trajectory
	size_t keyframes = 0;
	/** Times a scan due to become a keyframe was anchored at an existing one instead
	 * (CKeyframeReuse: ground the map already has). */
	size_t keyframesReused = 0;
	/** Keyframes of an older session (a continued map) that show a scan of this session
	 * since it reused them (the grid and the saved map show the place as it is now). */
	size_t keyframesRenewed = 0;
	size_t skippedScans = 0;    //!< too few valid returns
	size_t unmatchedScans = 0;  //!< no acceptable local match: the prediction was kept
	/** Scans whose pose was off their neighbours' odometry chain at the end of the run and
	 * was settled onto it (settleIsolatedScans). */
	size_t scansSettled = 0;
	/** Keyframes whose scan matched nothing online (mid-run, linked by odometry), re-matched
	 * at the end of the run against the map around them and moved (CKeyframeRematcher), and
	 * those left on their odometry prior (no evidence, or the match confirmed the pose). */
	size_t keyframesRematched = 0, keyframesLeftUnmatched = 0;
	/** Keyframes' patch links that no pairwise match confirmed, among returns sparser than
	 * the line fits' radius, whose covariance local registration widened (a hall's far
	 * walls; CLocalRegistration::patchLinksWidened). */
	size_t patchLinksWidened = 0;
	/** Keyframes whose patch match failed from the prior and passed when started where their
	 * pairwise matches agreed (CLocalRegistration::keyframesReseeded). */
	size_t keyframesReseeded = 0;
	size_t odometryRejected = 0;  //!< scans whose match disagreed with odometry beyond the gate
	size_t glitchesRecovered = 0;  //!< of those, recovered by the wide rotational search
	/** Odometry steps beyond any motion of the robot (a reset, a reboot, a re-based frame:
	 * CMotionPredictor), the scan's pose predicted without them. */
	size_t odometryJumps = 0;
	size_t odometryLinks = 0, scanMatchLinks = 0, loopClosureLinks = 0;
	size_t loopClosures = 0;  //!< accepted loop-closure events
	size_t revisitLinks = 0;  //!< links added by the end-of-run revisit sweep (CRevisitLinker)
	/** Loop links the final optimisation down-weighted below [PoseGraphOptimizer]
	 * reject_scale (the links it treats as false), then disabled. */
	size_t finalRejectedLinks = 0;
	size_t ignoredObservations = 0;  //!< observations of kinds the builder does not use
	/** Times the mapping thread had to wait for a loop search's result (it was not done by
	 * the keyframe it is due), and the time waited [s]. */
	size_t loopResultWaits = 0;
	double loopResultWaitSeconds = 0;
	double loopResultWaitMaxSeconds = 0;  //!< the longest single wait [s]
	/** [keyframes] The most keyframes between a loop search and the application of its
	 * result ([LoopCloser] result_delay_keyframes, worker_budget_ms). */
	size_t loopResultDelayMax = 0;
	/** [s] the de-skewing's sweep time at the end ([MapBuilder] scan_sweep_time_s, or
	 * estimated online: CSweepEstimator), whether it was estimated, and the scan pairs. */
	double sweepTime = 0;
	bool sweepTimeEstimated = false;
	size_t sweepSamples = 0;
	/** [m] the laser's range noise std as estimated from its scans at the end
	 * (CRangeNoiseEstimate), and the scans denoised because it exceeded kNoisyLaserStd_m. */
	double rangeNoiseStd = 0;
	size_t scansDenoised = 0;
	/** CPU time of the mapping thread [s] (CLOCK_THREAD_CPUTIME_ID) placing scans (step 3:
	 * new keyframes with their window links and solve, reused keyframes, and the loop results
	 * applied at them), and applying loop results (steps 4-5 on the mapping thread: at
	 * keyframes, so within the placement, and in a live run as they become ready). */
	double placementCpuSeconds = 0, loopApplyCpuSeconds = 0;
};

class CMetricMapBuilderLRGC : public mrpt::slam::CMetricMapBuilder
{
public:
	explicit CMetricMapBuilderLRGC(const TLRGCParams& params = {});
	~CMetricMapBuilderLRGC() override;

	/** Replaces the parameters; only allowed before the first scan. */
	void setParams(const TLRGCParams& params);
	const TLRGCParams& params() const { return m_params; }

	// --- mrpt::slam::CMetricMapBuilder ---
	/** Clears the map; with `initialMap` (any CSimpleMap, e.g. icp-slam's), mapping continues
	 * that map: its keyframes (first 2D laser scan of each entry) become graph nodes at their
	 * stored poses, each linked to the previous one by a scan match (by the stored relative
	 * pose where the match fails), and the places the map revisits by the revisit linker's
	 * loop links, so loop closures keep the old map's loops. `x0` sets the pose of the next
	 * scan (default: the last keyframe of `initialMap`, or the origin); see also
	 * startSessionAt(). The old keyframes are not scans of this run (trajectory()); where
	 * this run sees the world changed, its view wins (TKeyframe::session). */
	void initialize(const mrpt::maps::CSimpleMap& initialMap = mrpt::maps::CSimpleMap(),
					const mrpt::poses::CPosePDF* x0 = nullptr) override;
	/** Continues a map saved by lrgc exactly: the keyframes of `keyframes` (entry i = node i)
	 * with the graph `graph` (poses, links, link types, disabled links;
	 * lrgc_apps/io/PoseGraphText.h) as they were. `laserLabel`: the scans to take from each
	 * entry (empty: the first one). `sessions`: each node's mapping session as saved
	 * (TKeyframe::session; empty: all 0); this run maps the session after the newest. Throws
	 * if the sizes differ or an entry has no such scan. */
	void initialize(const mrpt::maps::CSimpleMap& keyframes, const CPoseGraph& graph,
					const std::string& laserLabel = {},
					const std::vector<size_t>& sessions = {});
	/** The next scan starts a new session at `scanInMap` (from global localisation, with its
	 * covariance `cov` [m^2, rad^2]): it becomes a keyframe linked to the old map by a scan
	 * match against the old keyframes around it (by `cov` if that fails), and the local
	 * registration window restarts there instead of joining the old map's last keyframe. */
	void startSessionAt(const mrpt::math::TPose2D& scanInMap, const Eigen::Matrix3d& cov);
	/** The next scan starts a piece of its own (a session whose place in the map is not
	 * known, CMetricMapBuilderLRGC_pieces.cpp): a keyframe at its odometry pose (the identity
	 * without odometry) linked to nothing, and the piece is mapped in that frame, local
	 * registration and loop closing within it, until joinPiece() places it in the map. */
	void startPiece();
	/** The map's keyframes now in the graph are held where they are from now on: the loop
	 * closures and the final optimisation move only the keyframes added later (the saved
	 * map's poses, and so its users' frame and its trajectory, stay as they were; as a
	 * frozen trajectory in Cartographer). */
	void freezeMap();
	/** The piece's first keyframe while it is not joined to the map; nullopt otherwise. */
	std::optional<size_t> pieceFirstNode() const { return m_pieceFirst; }
	/** Joins the piece to the map: its keyframe `node` lies at `nodeInMap` (global
	 * correlation, covariance `cov` [m^2, rad^2], map axes). The loop results in hand are
	 * applied first; a scan match of `node` against the map's keyframes around it refines the
	 * place; the whole piece (keyframes, scans, the robot) moves into the map's frame, and a
	 * loop link ties `node` to the nearest map keyframe. Returns the (map <- piece) applied. */
	mrpt::math::TPose2D joinPiece(size_t node, const mrpt::math::TPose2D& nodeInMap,
								  const Eigen::Matrix3d& cov);
	/** Why joinPiece(node, nodeInMap, cov) would link the piece by the correlation alone:
	 * the scan match of `node` against the map's keyframes around `nodeInMap` failed or does
	 * not confirm it (linkToMap); empty where it confirms it, and where no map keyframe lies
	 * within [LoopCloser] overlap_radius_m of it (nothing to check it against). Requires
	 * pieceFirstNode(). */
	std::string pieceJoinProblem(size_t node, const mrpt::math::TPose2D& nodeInMap,
								 const Eigen::Matrix3d& cov) const;
	/** The laser the map is built from (first seen, or restored). */
	const std::string& laserLabel() const { return m_lasers.label(); }
	mrpt::poses::CPose3DPDF::Ptr getCurrentPoseEstimation() const override;
	void processActionObservation(mrpt::obs::CActionCollection& action,
								  mrpt::obs::CSensoryFrame& observations) override;
	void getCurrentlyBuiltMap(mrpt::maps::CSimpleMap& out_map) const override;
	unsigned int getCurrentlyBuiltMapSize() override;
	/** A CMultiMetricMap holding the occupancy grid of the current estimate, brought up to
	 * date by the call (CIncrementalGrid: the keyframes added or moved since the last call
	 * are inserted, everything only after a loop closure moved old keyframes). */
	const mrpt::maps::CMultiMetricMap* getCurrentlyBuiltMetricMap() const override;
	/** Saves the occupancy grid of the current estimate; the format follows the file's
	 * extension (.png, .bmp, ...); formatEMF_BMP is ignored. */
	void saveCurrentEstimationToImage(const std::string& file,
									  bool formatEMF_BMP = true) override;

	// --- lone observations (rawlogs in the observations-only layout, CARMEN, live) ---
	/** Odometry (CObservationOdometry) or a 2D laser scan; other kinds are counted and
	 * ignored. */
	void processObservation(const mrpt::obs::CObservation::Ptr& obs);

	/** End of the run: the revisit sweep (CRevisitLinker), the re-match of the keyframes no
	 * scan matched online (CKeyframeRematcher), final optimisation of the whole graph (paper
	 * 2.4, last paragraph), then every scan placed between its keyframes. */
	void finish();

	/** A way to stop the long computations (StopToken.h), from any thread: once `stop` is
	 * stopped, a loop search in hand or queued ends early and adds nothing, the scan
	 * matches of the scan in hand (local registration, its wide rotational search, keyframe
	 * reuse) end early and match nothing, and finish() ends its revisit sweep, its re-match of
	 * unmatched keyframes and its final optimisation at their next step, so that what was
	 * mapped can be saved at once (the estimate as the loop closures left it). Kept across
	 * initialize(); from the mapping thread, before or between scans. */
	void setStopToken(const CStopToken& stop);

	// --- results ---
	TTrajectory trajectory() const;  //!< one pose per scan, at its timestamp, file order
	/** Timestamp of the last scan placed (default-constructed before the first). O(1). */
	mrpt::Clock::time_point lastScanTimestamp() const;
	const CPoseGraph& graph() const { return m_graph; }
	const TKeyframes& keyframes() const { return m_keyframes; }
	const TMapBuilderStats& stats() const { return m_stats; }
	TMapBuilderStats statsCopy() const;  //!< stats(), safe from another thread
	/** The mapped laser, the scans of other lasers ignored, the readings range-limited. */
	const CLaserSelector& lasers() const { return m_lasers; }
	/** Loop-closing counters and per-closure times (empty stats if loop closing is off). */
	TLoopCloserStats loopCloserStats() const;
	/** Occupancy grid of the current estimate, from the keyframes' scans (a copy). */
	std::shared_ptr<mrpt::maps::COccupancyGridMap2D> buildOccupancyGrid() const;
	/** What the grid is built from: each keyframe's laser (shared, never modified) at its
	 * current pose; a snapshot for building the grid elsewhere (CIncrementalGrid). */
	TGridKeyframes gridKeyframes() const;
	/** Resolution and ray length of the grid, and the keyframes the local window moves. */
	TGridSettings gridSettings() const;
	/** Warnings since the last call (skipped scans, ...), for the caller to report. */
	std::vector<std::string> takeWarnings();

private:
	struct TScanRecord
	{
		mrpt::Clock::time_point timestamp;
		size_t node;                      //!< keyframe the scan hangs from
		mrpt::math::TPose2D robotInNode;  //!< (node <- robot at the scan)
		/** The predicted step into this scan, (previous scan <- this scan), and whether it
		 * came from odometry (settleIsolatedScans). */
		mrpt::math::TPose2D step{0, 0, 0};
		Eigen::Matrix3d stepCov = Eigen::Matrix3d::Identity();  //!< of `step` (its model)
		/** TRegistration::cov, widened where returns are sparse (m_lastScanSmoothingCov);
		 * deferred ones settled a few scans later (recordScan). */
		CLazyCovariance registrationCov{Eigen::Matrix3d::Zero()};
		bool stepFromOdometry = false;
		bool keyframe = false;  //!< the scan is its node's own (a new keyframe)
		bool matched = true;    //!< its registration matched (TRegistration::matched)
	};

	// The story of one scan (CMetricMapBuilderLRGC.cpp), its steps in the paper's order.
	void processScan(const mrpt::obs::CObservation2DRangeScan::Ptr& laser,
					 const mrpt::obs::CSensoryFrame::Ptr& observations);
	std::optional<TScan2D> convertScan(const mrpt::obs::CObservation2DRangeScan& laser,
									   const mrpt::math::TPose2D& sweep);
	TRegistration registerLocally(const TScan2D& scan, const TMotionPrediction& prediction);
	void followRobot(const mrpt::obs::CObservation2DRangeScan& laser, const TScan2D& scan,
					 const TMotionPrediction& prediction, const mrpt::math::TPose2D& sweep,
					 const TRegistration& reg);
	void recordRegistration(const mrpt::obs::CObservation2DRangeScan& laser,
							const TMotionPrediction& prediction, const TRegistration& reg);
	void placeScan(const mrpt::obs::CObservation2DRangeScan::Ptr& laser,
				   const mrpt::obs::CSensoryFrame::Ptr& observations, TScan2D&& scan,
				   const TRegistration& reg, size_t scanIndex);
	void enterReusedKeyframe(const TReusedKeyframe& reused, const TRegistration& reg,
							 const mrpt::obs::CObservation2DRangeScan::Ptr& laser);
	void enterNewKeyframe(const mrpt::obs::CObservation2DRangeScan::Ptr& laser,
						  const mrpt::obs::CSensoryFrame::Ptr& observations, TScan2D&& scan,
						  const TRegistration& reg, size_t scanIndex);
	void closeLoops(bool newKeyframe);
	void takeReadyLoopResults();
	/** Records the scan in the trajectory, hanging from `node`, with the step predicted for it.
	 */
	void recordScan(mrpt::Clock::time_point stamp, size_t node,
					const mrpt::math::TPose2D& robotInNode, bool keyframe = false);
	/** End of the run: scans left off by an isolated registration follow the odometry between
	 * their neighbours (IsolatedScans.h), then every scan that is not a keyframe is placed
	 * between its keyframes by its registration and the odometry (ScanSmoothing.h). */
	void settleIsolatedScans();
	/** End of the run, before the final optimisation: the keyframes whose scan matched
	 * nothing online, re-matched against the map around them (KeyframeRematch.h); the other
	 * scans hanging from a keyframe moved keep their place in the map. */
	void rematchUnmatchedKeyframes();
	/** End of the run, before the final optimisation: the session's first keyframe, placed
	 * online by the first matches against it alone, re-matched against the map around it as
	 * an unmatched keyframe is (KeyframeRematch.h); where it moves, the map is moved rigidly
	 * instead, so that the first pose stays where the session started it. */
	void rematchFirstKeyframe();
	/** The end-of-run re-matcher of both, with this builder's parameters and stop token. */
	CKeyframeRematcher keyframeRematcher() const;
	/** Takes in what applying loop results did (links, closures, moved poses). */
	void recordLoopUpdate(const TLoopUpdate& u);
	bool isNewKeyframe(const mrpt::math::TPose2D& scanInMap) const;
	/** The keyframe the robot is at: the scans hang from it, keyframe distances count from it.
	 */
	size_t anchor() const;
	void linkReused(const TReusedKeyframe& c, const TRegistration& reg);
	double stepSeconds(const TMotionPrediction& prediction) const;
	mrpt::math::TPose2D sweepMotion(const TMotionPrediction& prediction) const;
	size_t addKeyframe(const mrpt::obs::CObservation2DRangeScan::Ptr& laser,
					   const mrpt::obs::CSensoryFrame::Ptr& observations, TScan2D&& scan,
					   const mrpt::math::TPose2D& scanInMap, size_t scanIndex);
	TLink odometryLink(size_t from, size_t to) const;
	mrpt::obs::CObservation2DRangeScan::Ptr acceptLaser(
		const mrpt::obs::CObservation2DRangeScan::Ptr& laser);
	void warn(std::string message);
	// The grid (CMetricMapBuilderLRGC_grid.cpp).
	TGridKeyframes gridKeyframesLocked() const;
	const std::shared_ptr<mrpt::maps::COccupancyGridMap2D>& updatedGridLocked() const;
	/** The base's critical section, also from const getters (it guards the state, not the
	 * object's constness). */
	std::unique_lock<std::mutex> lockMap() const
	{
		return std::unique_lock<std::mutex>(const_cast<std::mutex&>(critZoneChangingMap));
	}
	// Continuing a map (CMetricMapBuilderLRGC_continue.cpp).
	void resetState();
	void adoptKeyframes(const mrpt::maps::CSimpleMap& map, const std::string& laserLabel,
						bool all);
	void linkChainAndRevisits();
	void linkSessionStart(size_t node);
	/** A loop link from the nearest of the keyframes 0..mapEnd-1 to `node`, whose map pose is
	 * guessed at `guess` with covariance `cov` (map axes): by a scan match against the map's
	 * keyframes around it where the match confirms the guess, else by the guess. */
	struct TMapLink
	{
		TLink link;
		mrpt::math::TPose2D nodeInMap;  //!< where the link puts `node`
		std::string problem;            //!< why the match was not used; empty if it was
		bool mapAround = false;  //!< a map keyframe lies within overlap_radius_m: matched
	};
	TMapLink linkToMap(size_t node, const mrpt::math::TPose2D& guess,
					   const Eigen::Matrix3d& cov, size_t mapEnd) const;
	void enterNewestKeyframes();
	void showNewerScan(size_t node, const mrpt::obs::CObservation2DRangeScan::Ptr& laser,
					   const mrpt::math::TPose2D& robotInNode);

	TLRGCParams m_params;
	CStopToken m_stop;
	std::unique_ptr<CMotionPredictor> m_predictor;
	std::unique_ptr<CSweepEstimator> m_sweep;
	CRangeNoiseEstimate m_rangeNoise;  //!< the laser's range noise, from the scans
	std::unique_ptr<CLocalRegistration> m_local;
	std::unique_ptr<CKeyframeReuse> m_reuse;
	std::unique_ptr<CLoopClosing> m_loops;  //!< null with loop closing off
	friend struct TLoopClosingTestAccess;   // tests: a slow worker (tests/support)
	std::chrono::milliseconds m_loopSearchExtraDelay{
		0};  //!< tests only; kept across initialize()
	CPoseGraph m_graph;
	TKeyframes m_keyframes;
	std::vector<TScanRecord> m_scans;
	/** m_scans below this index hold known registration covariances (recordScan). */
	size_t m_scansSettled = 0;
	TMapBuilderStats m_stats;
	CLaserSelector m_lasers;  //!< the laser the map is built from, its range limits

	mrpt::math::TPose2D m_lastScanInMap{0, 0, 0};
	CLazyCovariance m_lastScanCov{Eigen::Matrix3d::Zero()};  //!< TRegistration::cov
	/** m_lastScanCov of a matched scan widened as a lone patch match's (lonePatchLinkCov):
	 * what the end of the run's smoothing weighs its registration by (TScanRecord). */
	CLazyCovariance m_lastScanSmoothingCov{Eigen::Matrix3d::Zero()};
	std::optional<mrpt::math::TPose2D> m_nextScanPrior;  //!< from initialize(x0)
	/** Set by startSessionAt(): the next scan starts a session; the covariance of its pose. */
	std::optional<Eigen::Matrix3d> m_sessionStartCov;
	/** startPiece(): the first keyframe of the piece not yet joined; the next scan starts it.
	 */
	std::optional<size_t> m_pieceFirst;
	bool m_pieceStartPending = false;
	size_t m_frozenNodes = 0;  //!< freezeMap(): nodes below it are held fixed
	/** Motion since the anchor keyframe (composed per-scan steps; from a reused keyframe, the
	 * registered offset first) and whether it came from trustworthy odometry: this becomes
	 * the odometry link of the next keyframe. */
	mrpt::math::TPose2D m_motionSinceKeyframe{0, 0, 0};
	/** Where the robot took its anchor keyframe, in the anchor's frame: zero for a new
	 * keyframe, the registered offset for a reused one. Keyframe distances count from it. */
	mrpt::math::TPose2D m_anchorOffset{0, 0, 0};
	bool m_odometryTrustedSinceKeyframe = true;
	/** The registered path [m] and turn [rad] since the last keyframe taken (new or reused),
	 * summed over the scans' steps: the loop worker's budget follows it (closeLoops). */
	double m_pathSinceKeyframe = 0, m_turnSinceKeyframe = 0;
	/** The current scan's predicted step, its covariance and source, for its TScanRecord. */
	mrpt::math::TPose2D m_scanStep{0, 0, 0};
	Eigen::Matrix3d m_scanStepCov = Eigen::Matrix3d::Identity();
	bool m_scanStepFromOdometry = false;
	bool m_scanMatched = true;  //!< the current scan's registration matched (TScanRecord)
	/** The session being mapped (TKeyframe::session): 0 in a plain run, 1 once a saved map is
	 * continued. */
	size_t m_session = 0;

	std::vector<std::string> m_warnings;
	mutable std::unique_ptr<mrpt::maps::CMultiMetricMap> m_metricMap;
	mutable bool m_metricMapDirty = true;
	mutable std::unique_ptr<CIncrementalGrid> m_grid;  //!< held by m_metricMap
};

}  // namespace lrgc
