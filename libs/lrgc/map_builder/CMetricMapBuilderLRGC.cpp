#include <lrgc/map_builder/CMetricMapBuilderLRGC.h>

#include <lrgc/common/se2.h>
#include <lrgc/local_registration/LocalRegistration.h>
#include <lrgc/local_registration/MotionPredictor.h>
#include <lrgc/loop_closing/LoopCloser.h>

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

CMetricMapBuilderLRGC::~CMetricMapBuilderLRGC() = default;

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
	return std::exchange(m_warnings, {});
}

// ---------------------------------------------------------------------------------------
// The story of one scan (paper fig. 6).
// ---------------------------------------------------------------------------------------
void CMetricMapBuilderLRGC::processScan(
	const mrpt::obs::CObservation2DRangeScan::Ptr& laser,
	const mrpt::obs::CSensoryFrame::Ptr& observations)
{
	// 1. Predict, and de-skew the scan by the predicted motion over its sweep.
	const TMotionPrediction prediction = m_predictor->predict(laser->timestamp);
	TScanConversionStats conv;
	TScan2D scan = scanFromObservation(*laser, &conv, sweepMotion(prediction));
	if (scan.points.size() < m_params.builder.min_scan_points)
	{
		++m_stats.skippedScans;
		warn(mrpt::format(
			"scan at t=%.6f skipped: %zu valid returns of %zu (min %zu)",
			mrpt::Clock::toDouble(laser->timestamp), scan.points.size(), conv.total,
			m_params.builder.min_scan_points));
		return;
	}

	const TPose2D priorInMap = m_nextScanPrior ? *m_nextScanPrior
		: m_scans.empty()						 ? TPose2D(0, 0, 0)
												 : compose(m_lastScanInMap, prediction.motion);
	m_nextScanPrior.reset();

	// 2. Register locally against the last K keyframes.
	const TRegistration reg =
		m_local->registerScan(m_graph, m_keyframes, scan, priorInMap, prediction);
	if (!reg.matched && m_graph.numNodes() > 0) ++m_stats.unmatchedScans;
	if (reg.odometryRejected) ++m_stats.odometryRejected;
	if (reg.wideSearch && reg.odometryRejected && prediction.fromOdometry)
	{
		++m_stats.glitchesRecovered;
		warn(mrpt::format(
			"odometry glitch at t=%.6f: the odometry step (%.2f m, %.1f deg) does not fit the "
			"scans; recovered by a wide rotational search, odometry link down-weighted",
			mrpt::Clock::toDouble(laser->timestamp), translationNorm(prediction.motion),
			mrpt::RAD2DEG(prediction.motion.phi)));
	}
	if (!prediction.fromOdometry || reg.odometryRejected) m_odometryTrustedSinceKeyframe = false;
	m_motionSinceKeyframe = compose(m_motionSinceKeyframe, prediction.motion);
	m_predictor->commitScan(laser->timestamp, between(m_lastScanInMap, reg.scanInMap));
	m_lastScanInMap = reg.scanInMap;
	m_lastScanCov = reg.cov;
	const size_t scanIndex = m_stats.scans++;

	// 3. Keyframe: add to the graph, link to the window, re-estimate the window.
	const bool sessionStart = m_sessionStartCov.has_value();
	if (m_graph.numNodes() == 0 || sessionStart || isNewKeyframe(reg.scanInMap))
	{
		const size_t node =
			addKeyframe(laser, observations, std::move(scan), reg.scanInMap, scanIndex);
		if (sessionStart) linkSessionStart(node);  // to the old map, by a scan match
		else if (node > 0)
		{
			m_stats.scanMatchLinks +=
				m_local->linkAndOptimize(m_graph, m_keyframes, odometryLinkToNewest());
			++m_stats.odometryLinks;
			// 4. Look for a loop and close it.
			if (m_loopCloser) lookForLoop();
		}
		m_lastScanInMap = m_graph.pose(node);
		m_motionSinceKeyframe = TPose2D(0, 0, 0);
		m_odometryTrustedSinceKeyframe = true;
		m_scans.push_back({laser->timestamp, node, TPose2D(0, 0, 0)});
	}
	else
	{
		const size_t newest = m_graph.numNodes() - 1;
		m_scans.push_back(
			{laser->timestamp, newest, between(m_graph.pose(newest), reg.scanInMap)});
	}
	m_metricMapDirty = true;
}

void CMetricMapBuilderLRGC::lookForLoop()
{
	const auto closure = m_loopCloser->process(m_graph, m_keyframes);
	if (!closure) return;
	++m_stats.loopClosures;
	m_stats.loopClosureLinks += 1 + closure->rematchLinks;
	if (closure->optimized)
	{
		m_local->invalidate();
		MRPT_LOG_INFO_FMT(
			"loop closed: keyframe %zu -> %zu (score %.2f, ambiguity %.2f), %zu re-matched "
			"links, %.1f ms",
			closure->newNode, closure->oldNode, closure->score, closure->ambiguity,
			closure->rematchLinks, 1e3 * closure->seconds);
	}
}

TLoopCloserStats CMetricMapBuilderLRGC::loopCloserStats() const
{
	return m_loopCloser ? m_loopCloser->stats() : TLoopCloserStats{};
}

// The robot's motion over the laser sweep: the predicted step scaled by sweep / step time.
// Where the logged intervals are not the true ones (a jittered clock, or a step shorter than
// half the scan period: the first of a jitter burst) the step time is the mean scan period.
TPose2D CMetricMapBuilderLRGC::sweepMotion(const TMotionPrediction& prediction) const
{
	const double sweep = m_params.builder.scan_sweep_time;
	const double step =
		m_predictor->clockJittered() || prediction.stepSeconds < 0.5 * m_predictor->scanPeriod()
		? m_predictor->meanScanPeriod()
		: prediction.stepSeconds;
	if (sweep <= 0 || step <= 0) return TPose2D(0, 0, 0);
	const double k = std::min(1.0, sweep / step);
	return TPose2D(k * prediction.motion.x, k * prediction.motion.y, k * prediction.motion.phi);
}

bool CMetricMapBuilderLRGC::isNewKeyframe(const TPose2D& scanInMap) const
{
	const TPose2D d = between(m_graph.pose(m_graph.numNodes() - 1), scanInMap);
	return translationNorm(d) >= m_params.builder.keyframe_distance ||
		std::abs(d.phi) >= m_params.builder.keyframe_angle;
}

size_t CMetricMapBuilderLRGC::addKeyframe(
	const mrpt::obs::CObservation2DRangeScan::Ptr& laser,
	const mrpt::obs::CSensoryFrame::Ptr& observations, TScan2D&& scan, const TPose2D& scanInMap,
	size_t scanIndex)
{
	const size_t node = m_graph.addNode(scanInMap);
	ASSERT_EQUAL_(node, m_keyframes.size());
	m_keyframes.push_back({std::move(scan), observations, laser, scanIndex});
	++m_stats.keyframes;
	return node;
}

// The odometry link (previous keyframe -> newest keyframe): the odometry motion composed
// over the scans in between with its proportional noise; where odometry was absent or
// rejected as a glitch, the registered motion with the weak constant-velocity noise, so
// the graph stays connected without the link pulling the map.
TLink CMetricMapBuilderLRGC::odometryLinkToNewest() const
{
	const size_t to = m_graph.numNodes() - 1, from = to - 1;
	TLink link;
	link.from = from;
	link.to = to;
	link.type = LinkType::Odometry;
	if (m_odometryTrustedSinceKeyframe)
	{
		link.toInFrom = m_motionSinceKeyframe;
		link.information = m_predictor->odometryCov(m_motionSinceKeyframe).inverse();
	}
	else
	{
		link.toInFrom = between(m_graph.pose(from), m_graph.pose(to));
		link.information = m_predictor->constantVelocityCov().inverse();
	}
	return link;
}

// ---------------------------------------------------------------------------------------
// Observation intake.
// ---------------------------------------------------------------------------------------
void CMetricMapBuilderLRGC::processObservation(const mrpt::obs::CObservation::Ptr& obs)
{
	ASSERT_(obs);
	if (auto odo = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(obs))
		m_predictor->addOdometryAbsolute(odo->odometry.asTPose());
	else if (auto laser = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs))
	{
		if (m_laserLabel.empty()) m_laserLabel = laser->sensorLabel;
		if (laser->sensorLabel != m_laserLabel) { ++m_stats.ignoredObservations; return; }
		auto sf = mrpt::obs::CSensoryFrame::Create();
		sf->insert(laser);
		processScan(laser, sf);
	}
	else
		++m_stats.ignoredObservations;
}

void CMetricMapBuilderLRGC::processActionObservation(
	mrpt::obs::CActionCollection& action, mrpt::obs::CSensoryFrame& observations)
{
	if (auto odo = action.getBestMovementEstimation(); odo && odo->poseChange)
		m_predictor->addOdometryIncrement(odo->poseChange->getMeanVal().asTPose());
	auto sf = mrpt::obs::CSensoryFrame::Create(observations);
	mrpt::obs::CObservation2DRangeScan::Ptr laser;
	for (const auto& o : observations)
		if (auto l = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(o))
		{
			if (m_laserLabel.empty()) m_laserLabel = l->sensorLabel;
			if (l->sensorLabel == m_laserLabel && !laser) laser = l;
		}
		else if (auto od = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(o))
			m_predictor->addOdometryAbsolute(od->odometry.asTPose());
	if (laser) processScan(laser, sf);
	else ++m_stats.ignoredObservations;
}

}  // namespace lrgc
