#include <lrgc/map_builder/CMetricMapBuilderLRGC.h>

#include <lrgc/common/CpuTime.h>
#include <lrgc/common/se2.h>
#include <lrgc/local_registration/LocalRegistration.h>
#include <lrgc/local_registration/MotionPredictor.h>
#include <lrgc/local_registration/SweepEstimator.h>
#include <lrgc/loop_closing/LoopCloser.h>
#include <lrgc/loop_closing/LoopClosing.h>
#include <lrgc/map_builder/IncrementalGrid.h>
#include <lrgc/map_builder/KeyframeReuse.h>

#include <Eigen/Dense>

#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/poses/CPosePDF.h>

namespace lrgc
{
using mrpt::math::TPose2D;

CMetricMapBuilderLRGC::CMetricMapBuilderLRGC(const TLRGCParams& params)
{
	setLoggerName("CMetricMapBuilderLRGC");
	m_params = params;
	initialize();
}

// The loop-closing worker (and its far lane) and the window's helper thread may still run a job
// that reads keyframe scans through TScanRefs (raw pointers into m_keyframes): they are joined
// here, before the members they read are destroyed (members go in reverse order of declaration,
// and m_keyframes / m_scans are declared after them).
CMetricMapBuilderLRGC::~CMetricMapBuilderLRGC()
{
	m_loops.reset();
	m_local.reset();
}

void CMetricMapBuilderLRGC::setParams(const TLRGCParams& params)
{
	ASSERTMSG_(m_stats.scans == 0, "setParams() must be called before the first scan");
	m_params = params;
	initialize();
}

void CMetricMapBuilderLRGC::warn(std::string message)
{
	MRPT_LOG_WARN(message);
	m_warnings.push_back(std::move(message));
}

std::vector<std::string> CMetricMapBuilderLRGC::takeWarnings()
{
	const auto lock = lockMap();
	return std::exchange(m_warnings, {});
}

// ---------------------------------------------------------------------------------------
// The story of one scan (paper fig. 6): predict its pose, register it locally, place it (on
// its keyframe, on a keyframe the map already has, or as a new keyframe linked to the
// window), look for loops and close them (at a keyframe, in the background), record. Step 3
// (placeScan) is in CMetricMapBuilderLRGC_keyframes.cpp.
// ---------------------------------------------------------------------------------------
void CMetricMapBuilderLRGC::processScan(const mrpt::obs::CObservation2DRangeScan::Ptr& laser,
										const mrpt::obs::CSensoryFrame::Ptr& observations)
{
	if (m_loops && m_params.loop.apply_when_ready) takeReadyLoopResults();  // a live run
	const TMotionPrediction prediction = m_predictor->predict(laser->timestamp);
	const TPose2D sweep = sweepMotion(prediction);
	std::optional<TScan2D> scan = convertScan(*laser, sweep);
	if (!scan) return;  // too few returns: skipped, with a warning
	const TRegistration reg = registerLocally(*scan, prediction);
	// Placed by the odometry's alternative (MotionPredictor.h): the scan followed that.
	const TMotionPrediction followed =
		reg.alternativePrior ? followingAlternative(prediction) : prediction;
	followRobot(*laser, *scan, followed, sweep, reg);
	recordRegistration(*laser, followed, reg);
	CCpuTimer placement(m_stats.placementCpuSeconds);
	placeScan(laser, observations, std::move(*scan), reg, m_stats.scans++);
	m_metricMapDirty = true;
}

// Step 1b: the scan as points in the robot frame, de-skewed by the predicted motion over its
// sweep, denoised if the laser's range noise (estimated from the scans) is large; none
// (counted, with a warning) if it has too few valid returns to match.
std::optional<TScan2D> CMetricMapBuilderLRGC::convertScan(
	const mrpt::obs::CObservation2DRangeScan& laser, const TPose2D& sweep)
{
	TScanConversionStats conv;
	const double rangeNoise = m_rangeNoise.add(rangeNoiseStd(laser));
	m_stats.rangeNoiseStd = rangeNoise;
	if (rangeNoise > kNoisyLaserStd_m && m_stats.scansDenoised++ == 0)
		warn(
			mrpt::format("the laser's range noise is %.2f m (estimated from its scans, from "
						 "t=%.6f): its scans are denoised and the matching gates widened",
						 rangeNoise, mrpt::Clock::toDouble(laser.timestamp)));
	TScan2D scan = scanFromObservation(laser, &conv, sweep, rangeNoise);
	if (scan.points.size() >= m_params.builder.min_scan_points) return scan;
	++m_stats.skippedScans;
	warn(mrpt::format("scan at t=%.6f skipped: %zu valid returns of %zu (min %zu)",
					  mrpt::Clock::toDouble(laser.timestamp), scan.points.size(), conv.total,
					  m_params.builder.min_scan_points));
	return std::nullopt;
}

// Step 2: register against the last K keyframes, from the predicted pose (the previous scan's
// composed with the predicted motion; a given prior for a session's first scan).
TRegistration CMetricMapBuilderLRGC::registerLocally(const TScan2D& scan,
													 const TMotionPrediction& prediction)
{
	if (m_pieceStartPending)  // a piece's first scan: at its odometry pose (startPiece)
	{
		m_lastScanInMap = m_predictor->odometryNow().value_or(TPose2D(0, 0, 0));
		m_nextScanPrior = m_lastScanInMap;
	}
	TMotionPrediction forScan = prediction;
	// A given prior is not the last scan's pose composed with the motion: no alternative.
	if (m_nextScanPrior || m_scans.empty()) forScan.alternative.reset();
	const TPose2D priorInMap = m_nextScanPrior   ? *m_nextScanPrior
							   : m_scans.empty() ? TPose2D(0, 0, 0)
												 : compose(m_lastScanInMap, prediction.motion);
	m_nextScanPrior.reset();
	return m_local->registerScan(m_graph, m_keyframes, scan, priorInMap, forScan);
}

// The robot moved to the registered pose: the motion model, the sweep estimator and the
// motion since the anchor keyframe (the next odometry link) follow it.
void CMetricMapBuilderLRGC::followRobot(const mrpt::obs::CObservation2DRangeScan& laser,
										const TScan2D& scan,
										const TMotionPrediction& prediction,
										const TPose2D& sweep, const TRegistration& reg)
{
	if (!prediction.fromOdometry || reg.odometryRejected)
		m_odometryTrustedSinceKeyframe = false;
	m_motionSinceKeyframe = compose(m_motionSinceKeyframe, prediction.motion);
	m_scanStep = prediction.motion;
	m_scanStepCov = prediction.cov;
	m_scanStepFromOdometry = prediction.fromOdometry;
	m_scanMatched = reg.matched;
	const TPose2D step = between(m_lastScanInMap, reg.scanInMap);
	m_pathSinceKeyframe += translationNorm(step);
	m_turnSinceKeyframe += std::abs(step.phi);
	m_predictor->commitScan(laser.timestamp, step,
							prediction.fromOdometry && !reg.odometryRejected);
	const double dt = stepSeconds(prediction);
	m_sweep->observe(laser, scan, dt > 0 ? prediction.motion.phi / dt : 0.0, sweep.phi, step,
					 reg.matched);
	m_lastScanInMap = reg.scanInMap;
	m_lastScanCov = reg.cov;
	// lonePatchLinkCov's widening, on the covariance when it is known (a deferred one).
	const double widening =
		reg.matched ? sparseReturnsRatio(scan, m_params.matcher.normal_radius_m) : 1.0;
	m_lastScanSmoothingCov = widening <= 1
								 ? reg.cov
								 : reg.cov.then([widening](const Eigen::Matrix3d& c)
												{ return widenedPosition(c, widening); });
}

// Bookkeeping of step 2: unmatched scans, odometry glitches, the sweep estimate.
void CMetricMapBuilderLRGC::recordRegistration(const mrpt::obs::CObservation2DRangeScan& laser,
											   const TMotionPrediction& prediction,
											   const TRegistration& reg)
{
	if (!reg.matched && m_graph.numNodes() > 0) ++m_stats.unmatchedScans;
	if (reg.odometryRejected) ++m_stats.odometryRejected;
	if (reg.wideSearch && reg.odometryRejected && prediction.fromOdometry)
	{
		++m_stats.glitchesRecovered;
		warn(mrpt::format(
			"odometry glitch at t=%.6f: the odometry step (%.2f m, %.1f deg) does not fit the "
			"scans; recovered by a wide rotational search, odometry link down-weighted",
			mrpt::Clock::toDouble(laser.timestamp), translationNorm(prediction.motion),
			mrpt::RAD2DEG(prediction.motion.phi)));
	}
	if (prediction.odometryJump)
	{
		++m_stats.odometryJumps;
		warn(mrpt::format(
			"odometry jump at t=%.6f: a step of %.2f m, %.1f deg in %.2f s (a reset of the "
			"odometry?); the scan was placed %s, without it",
			mrpt::Clock::toDouble(laser.timestamp), translationNorm(prediction.odometryStep),
			mrpt::RAD2DEG(prediction.odometryStep.phi), prediction.stepSeconds,
			reg.matched ? "by its scan match" : "by constant velocity (no scan match)"));
	}
	m_stats.sweepTime = m_sweep->sweepTime();
	m_stats.sweepTimeEstimated = m_sweep->summary().estimated;
	m_stats.sweepSamples = m_sweep->summary().samples;
}

// Steps 4-5 at a keyframe taken (CLoopClosing): the loop results due are applied, and a new
// keyframe is handed over to look for a loop in the background. The travel since the last
// keyframe, in keyframe spacings, sets the loop worker's budget for this one.
void CMetricMapBuilderLRGC::closeLoops(bool newKeyframe)
{
	const double span = std::max(m_pathSinceKeyframe / m_params.builder.keyframe_distance_m,
								 m_turnSinceKeyframe / m_params.builder.keyframe_angle);
	m_pathSinceKeyframe = m_turnSinceKeyframe = 0;
	if (!m_loops) return;
	CCpuTimer apply(m_stats.loopApplyCpuSeconds);
	recordLoopUpdate(m_loops->afterKeyframe(m_graph, m_keyframes, newKeyframe, anchor(),
											m_lastScanInMap, span));
}

void CMetricMapBuilderLRGC::takeReadyLoopResults()
{
	CCpuTimer apply(m_stats.loopApplyCpuSeconds);
	recordLoopUpdate(m_loops->whenReady(m_graph, anchor(), m_lastScanInMap));
}

// What applied loop results changed: the window's patch is stale if poses moved; a loop link
// ties the robot to the map (keyframe reuse may trust it); closures are counted and logged.
void CMetricMapBuilderLRGC::recordLoopUpdate(const TLoopUpdate& u)
{
	if (u.posesMoved) m_local->invalidate();
	if (u.loopLinked) m_reuse->noteLoopLink(m_graph.numNodes() - 1);
	m_stats.loopClosures += u.closures.size();
	m_stats.loopClosureLinks += u.loopLinks;
	for (const TLoopClosure& c : u.closures)
		if (c.optimized)
			MRPT_LOG_INFO_FMT(
				"loop closed: keyframe %zu -> %zu (score %.2f, ambiguity %.2f), %zu re-matched "
				"links, %.1f ms",
				c.newNode, c.oldNode, c.score, c.ambiguity, c.rematchLinks, 1e3 * c.seconds);
	const TLoopScheduleStats& s = m_loops->schedule();
	m_stats.loopResultWaits = s.waits;
	m_stats.loopResultWaitSeconds = s.waitSeconds;
	m_stats.loopResultWaitMaxSeconds = s.waitMaxSeconds;
	m_stats.loopResultDelayMax = s.delayMax;
	m_metricMapDirty = true;
}

TLoopCloserStats CMetricMapBuilderLRGC::loopCloserStats() const
{
	const auto lock = lockMap();
	return m_loops ? m_loops->stats() : TLoopCloserStats{};
}

// The time of the predicted step [s]. Where the logged intervals are not the true ones (a
// jittered clock, or a step shorter than half the scan period: the first of a jitter burst)
// it is the mean scan period.
double CMetricMapBuilderLRGC::stepSeconds(const TMotionPrediction& prediction) const
{
	return m_predictor->clockJittered() ||
				   prediction.stepSeconds < 0.5 * m_predictor->scanPeriod()
			   ? m_predictor->meanScanPeriod()
			   : prediction.stepSeconds;
}

// The robot's motion over the laser sweep: the predicted step scaled by sweep / step time,
// the sweep time fixed or estimated (CSweepEstimator).
TPose2D CMetricMapBuilderLRGC::sweepMotion(const TMotionPrediction& prediction) const
{
	const double sweep = m_sweep->sweepTime(), step = stepSeconds(prediction);
	if (sweep <= 0 || step <= 0) return TPose2D(0, 0, 0);
	const double k = std::min(1.0, sweep / step);
	return TPose2D(k * prediction.motion.x, k * prediction.motion.y, k * prediction.motion.phi);
}

// ---------------------------------------------------------------------------------------
// Observation intake.
// ---------------------------------------------------------------------------------------
// The mapped laser's scan with its range limits applied, or null for another laser's
// (CLaserSelector counts it, and warns once when a second laser shows up unasked).
mrpt::obs::CObservation2DRangeScan::Ptr CMetricMapBuilderLRGC::acceptLaser(
	const mrpt::obs::CObservation2DRangeScan::Ptr& laser)
{
	auto mapped = m_lasers.select(laser);
	while (auto w = m_lasers.takeWarning()) warn(std::move(*w));
	return mapped;
}

void CMetricMapBuilderLRGC::processObservation(const mrpt::obs::CObservation::Ptr& obs)
{
	ASSERT_(obs);
	const auto lock = lockMap();
	if (auto odo = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(obs))
		m_predictor->addOdometryAbsolute(odo->odometry.asTPose());
	else if (auto laser = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs))
	{
		if (!(laser = acceptLaser(laser))) return;
		auto sf = mrpt::obs::CSensoryFrame::Create();
		sf->insert(laser);
		processScan(laser, sf);
	}
	else
		++m_stats.ignoredObservations;
}

void CMetricMapBuilderLRGC::processActionObservation(mrpt::obs::CActionCollection& action,
													 mrpt::obs::CSensoryFrame& observations)
{
	const auto lock = lockMap();
	if (auto odo = action.getBestMovementEstimation(); odo && odo->poseChange)
		m_predictor->addOdometryIncrement(odo->poseChange->getMeanVal().asTPose());
	auto sf = mrpt::obs::CSensoryFrame::Create(observations);
	mrpt::obs::CObservation2DRangeScan::Ptr laser;
	for (auto& o : *sf)
		if (auto l = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(o))
		{
			auto mapped = acceptLaser(l);
			if (mapped && !laser) o = laser = mapped;  // the frame keeps the range-limited scan
		}
		else if (auto od = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(o))
			m_predictor->addOdometryAbsolute(od->odometry.asTPose());
	if (laser)
		processScan(laser, sf);
	else
		++m_stats.ignoredObservations;
}

}  // namespace lrgc
