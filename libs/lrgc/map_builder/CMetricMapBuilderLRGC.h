/* CMetricMapBuilderLRGC: the LRGC map builder (Gutmann & Konolige 2000, section 2.4, fig. 6)
 * as an MRPT map builder, a drop-in for mrpt::slam::CMetricMapBuilderICP.
 *
 * The map is a graph (CPoseGraph): nodes are keyframe poses with their scans, links come
 * from odometry, scan matching and correlation. Each scan goes through a short story:
 *   1. predict its pose from odometry (or constant velocity without odometry);
 *   2. register it locally against the last K keyframes (CLocalRegistration);
 *   3. if it travelled far enough, add it to the graph as a keyframe, linked to the window,
 *      and re-estimate the window's poses (Lu & Milios over the last K only);
 *   4. look for a loop and close it (when the loop-closure stage is enabled).
 * Every scan, keyframe or not, is kept in the trajectory relative to its keyframe, so
 * optimisations move it along. The map is updated with every scan (anytime).
 */
#pragma once

#include <lrgc/loop_closing/LoopCloserStats.h>
#include <lrgc/map_builder/MapBuilderParams.h>
#include <lrgc/map_builder/Trajectory.h>
#include <lrgc/pose_graph/Keyframe.h>
#include <lrgc/pose_graph/PoseGraph.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/slam/CMetricMapBuilder.h>

#include <memory>
#include <optional>

namespace lrgc
{
// The stages are the builder's internals: users see its products (graph, keyframes,
// trajectory) and its parameters, not the classes that make them.
class CMotionPredictor;
class CLocalRegistration;
class CLoopCloser;
struct TMotionPrediction;

/** Counters of a run, for stats.json and logs. */
struct TMapBuilderStats
{
	size_t scans = 0;  //!< laser scans placed in the trajectory
	size_t keyframes = 0;
	size_t skippedScans = 0;  //!< too few valid returns
	size_t unmatchedScans = 0;  //!< no acceptable local match: the prediction was kept
	size_t odometryRejected = 0;  //!< scans whose match disagreed with odometry beyond the gate
	size_t glitchesRecovered = 0;  //!< of those, recovered by the wide rotational search
	size_t odometryLinks = 0, scanMatchLinks = 0, loopClosureLinks = 0;
	size_t loopClosures = 0;  //!< accepted loop-closure events
	size_t revisitLinks = 0;  //!< links added by the end-of-run revisit sweep (CRevisitLinker)
	size_t ignoredObservations = 0;  //!< observations of kinds the builder does not use
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
	 * startSessionAt(). The old keyframes are not scans of this run (trajectory()). */
	void initialize(
		const mrpt::maps::CSimpleMap& initialMap = mrpt::maps::CSimpleMap(),
		const mrpt::poses::CPosePDF* x0 = nullptr) override;
	/** Continues a map saved by lrgc exactly: the keyframes of `keyframes` (entry i = node i)
	 * with the graph `graph` (poses, links, link types, disabled links; PoseGraphText.h) as
	 * they were. `laserLabel`: the scans to take from each entry (empty: the first one).
	 * Throws if the sizes differ or an entry has no such scan. */
	void initialize(
		const mrpt::maps::CSimpleMap& keyframes, const CPoseGraph& graph,
		const std::string& laserLabel = {});
	/** The next scan starts a new session at `scanInMap` (from global localisation, with its
	 * covariance `cov` [m^2, rad^2]): it becomes a keyframe linked to the old map by a scan
	 * match against the old keyframes around it (by `cov` if that fails), and the local
	 * registration window restarts there instead of joining the old map's last keyframe. */
	void startSessionAt(const mrpt::math::TPose2D& scanInMap, const Eigen::Matrix3d& cov);
	/** The laser the map is built from (first seen, or restored). */
	const std::string& laserLabel() const { return m_laserLabel; }
	mrpt::poses::CPose3DPDF::Ptr getCurrentPoseEstimation() const override;
	void processActionObservation(
		mrpt::obs::CActionCollection& action, mrpt::obs::CSensoryFrame& observations) override;
	void getCurrentlyBuiltMap(mrpt::maps::CSimpleMap& out_map) const override;
	unsigned int getCurrentlyBuiltMapSize() override;
	/** A CMultiMetricMap holding the occupancy grid of the current estimate (rebuilt when
	 * the estimate has changed since the last call). */
	const mrpt::maps::CMultiMetricMap* getCurrentlyBuiltMetricMap() const override;
	/** Saves the occupancy grid of the current estimate; the format follows the file's
	 * extension (.png, .bmp, ...); formatEMF_BMP is ignored. */
	void saveCurrentEstimationToImage(const std::string& file, bool formatEMF_BMP = true) override;

	// --- lone observations (rawlogs in the observations-only layout, CARMEN, live) ---
	/** Odometry (CObservationOdometry) or a 2D laser scan; other kinds are counted and
	 * ignored. */
	void processObservation(const mrpt::obs::CObservation::Ptr& obs);

	/** End of the run: final optimisation of the whole graph (paper 2.4, last paragraph). */
	void finish();

	// --- results ---
	TTrajectory trajectory() const;  //!< one pose per scan, at its timestamp, file order
	/** Timestamp of the last scan placed (default-constructed before the first). O(1). */
	mrpt::Clock::time_point lastScanTimestamp() const
	{
		return m_scans.empty() ? mrpt::Clock::time_point{} : m_scans.back().timestamp;
	}
	const CPoseGraph& graph() const { return m_graph; }
	const TKeyframes& keyframes() const { return m_keyframes; }
	const TMapBuilderStats& stats() const { return m_stats; }
	/** Loop-closing counters and per-closure times (empty stats if loop closing is off). */
	TLoopCloserStats loopCloserStats() const;
	/** Occupancy grid of the current estimate, from the keyframes' scans. */
	mrpt::maps::COccupancyGridMap2D::Ptr buildOccupancyGrid() const;
	/** Warnings since the last call (skipped scans, ...), for the caller to report. */
	std::vector<std::string> takeWarnings();

   private:
	struct TScanRecord
	{
		mrpt::Clock::time_point timestamp;
		size_t node;  //!< keyframe the scan hangs from
		mrpt::math::TPose2D robotInNode;  //!< (node <- robot at the scan)
	};

	void processScan(
		const mrpt::obs::CObservation2DRangeScan::Ptr& laser,
		const mrpt::obs::CSensoryFrame::Ptr& observations);
	void lookForLoop();
	bool isNewKeyframe(const mrpt::math::TPose2D& scanInMap) const;
	mrpt::math::TPose2D sweepMotion(const TMotionPrediction& prediction) const;
	size_t addKeyframe(
		const mrpt::obs::CObservation2DRangeScan::Ptr& laser,
		const mrpt::obs::CSensoryFrame::Ptr& observations, TScan2D&& scan,
		const mrpt::math::TPose2D& scanInMap, size_t scanIndex);
	TLink odometryLinkToNewest() const;
	void warn(std::string message);
	// Continuing a map (CMetricMapBuilderLRGC_continue.cpp).
	void resetState();
	void adoptKeyframes(const mrpt::maps::CSimpleMap& map, const std::string& laserLabel, bool all);
	void linkChainAndRevisits();
	void linkSessionStart(size_t node);

	TLRGCParams m_params;
	std::unique_ptr<CMotionPredictor> m_predictor;
	std::unique_ptr<CLocalRegistration> m_local;
	std::unique_ptr<CLoopCloser> m_loopCloser;
	CPoseGraph m_graph;
	TKeyframes m_keyframes;
	std::vector<TScanRecord> m_scans;
	TMapBuilderStats m_stats;
	std::string m_laserLabel;  //!< the laser the map is built from (first seen)

	mrpt::math::TPose2D m_lastScanInMap{0, 0, 0};
	Eigen::Matrix3d m_lastScanCov = Eigen::Matrix3d::Zero();
	std::optional<mrpt::math::TPose2D> m_nextScanPrior;  //!< from initialize(x0)
	/** Set by startSessionAt(): the next scan starts a session; the covariance of its pose. */
	std::optional<Eigen::Matrix3d> m_sessionStartCov;
	/** Motion since the newest keyframe (composed per-scan steps) and whether it came from
	 * trustworthy odometry: this becomes the odometry link of the next keyframe. */
	mrpt::math::TPose2D m_motionSinceKeyframe{0, 0, 0};
	bool m_odometryTrustedSinceKeyframe = true;

	std::vector<std::string> m_warnings;
	mutable std::unique_ptr<mrpt::maps::CMultiMetricMap> m_metricMap;
	mutable bool m_metricMapDirty = true;
};

}  // namespace lrgc
