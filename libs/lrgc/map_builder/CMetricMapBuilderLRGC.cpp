#include <lrgc/map_builder/CMetricMapBuilderLRGC.h>

#include <lrgc/common/se2.h>
#include <lrgc/local_registration/LocalRegistration.h>
#include <lrgc/local_registration/MotionPredictor.h>
#include <lrgc/local_registration/SweepEstimator.h>
#include <lrgc/loop_closing/LoopClosingWorker.h>
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
	const auto lock = lockMap();
	return std::exchange(m_warnings, {});
}

// ---------------------------------------------------------------------------------------
// The story of one scan (paper fig. 6).
// ---------------------------------------------------------------------------------------
void CMetricMapBuilderLRGC::processScan(
	const mrpt::obs::CObservation2DRangeScan::Ptr& laser,
	const mrpt::obs::CSensoryFrame::Ptr& observations)
{
	// A live run takes a loop search's result as soon as it is ready.
	if (m_loopWorker && m_params.loop.apply_when_ready) serviceLoopClosing(false);

	// 1. Predict, and de-skew the scan by the predicted motion over its sweep.
	const TMotionPrediction prediction = m_predictor->predict(laser->timestamp);
	TScanConversionStats conv;
	const TPose2D sweep = sweepMotion(prediction);
	TScan2D scan = scanFromObservation(*laser, &conv, sweep);
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
	const double step = stepSeconds(prediction);
	m_sweep->observe(
		*laser, scan, step > 0 ? prediction.motion.phi / step : 0.0, sweep.phi,
		between(m_lastScanInMap, reg.scanInMap), reg.matched);
	m_stats.sweepTime = m_sweep->sweepTime();
	m_stats.sweepTimeEstimated = m_sweep->summary().estimated;
	m_stats.sweepSamples = m_sweep->summary().samples;
	m_lastScanInMap = reg.scanInMap;
	m_lastScanCov = reg.cov;
	const size_t scanIndex = m_stats.scans++;

	// 3. Keyframe: add to the graph, link to the window, re-estimate the window; or, on
	// ground the map already has, anchor at the keyframe there (CKeyframeReuse).
	const bool sessionStart = m_sessionStartCov.has_value();
	const bool atStart = m_graph.numNodes() == 0 || sessionStart;
	if (!atStart && !isNewKeyframe(reg.scanInMap))
		m_scans.push_back(
			{laser->timestamp, anchor(), between(m_graph.pose(anchor()), reg.scanInMap)});
	else if (const auto reused = atStart || !reg.matched || reg.odometryRejected || reg.wideSearch
			 ? std::nullopt
			 : m_reuse->reusableKeyframe(
				   m_graph, m_keyframes, scan, reg.scanInMap, reg.cov, anchor(),
				   m_local->window()))
	{
		++m_stats.keyframesReused;
		linkReused(*reused, reg);
		m_local->enterKeyframe(reused->node, true, m_graph);
		const TPose2D inNode = between(m_graph.pose(reused->node), reg.scanInMap);
		m_motionSinceKeyframe = inNode;  // the odometry link of a later keyframe starts here
		m_anchorOffset = inNode;
		m_scans.push_back({laser->timestamp, reused->node, inNode});
		++m_keyframeClock;
		if (m_loopWorker) serviceLoopClosing(true, false);
	}
	else
	{
		const std::optional<size_t> previous = m_local->anchor();
		const size_t node =
			addKeyframe(laser, observations, std::move(scan), reg.scanInMap, scanIndex);
		m_local->enterKeyframe(node, false, m_graph);
		if (sessionStart) linkSessionStart(node);  // to the old map, by a scan match
		else if (previous)
		{
			m_stats.scanMatchLinks += m_local->linkAndOptimize(
				m_graph, m_keyframes, odometryLink(*previous, node));
			++m_stats.odometryLinks;
			// 4. Look for a loop and close it (in the background).
			++m_keyframeClock;
			if (m_loopWorker) serviceLoopClosing(true);
		}
		m_lastScanInMap = m_graph.pose(node);
		m_motionSinceKeyframe = TPose2D(0, 0, 0);
		m_anchorOffset = TPose2D(0, 0, 0);
		m_odometryTrustedSinceKeyframe = true;
		m_scans.push_back({laser->timestamp, node, TPose2D(0, 0, 0)});
	}
	m_metricMapDirty = true;
}

// Step 4 with a worker (CLoopClosingWorker). At a keyframe, the results that are due are
// applied, in order: a search started at keyframe k is due at the keyframe the worker's
// schedule gives it (CLoopClosingWorker::due: k + result_delay_keyframes, or where the modelled worker
// finishes it; waited for if not done), or in a live run whenever it is ready. Then a
// search for the newest keyframe is queued, with what the worker's copy of the graph lacks.
void CMetricMapBuilderLRGC::serviceLoopClosing(bool atKeyframe, bool newKeyframe)
{
	const size_t newest = m_graph.numNodes() - 1;
	const auto& p = m_params.loop;
	while (m_loopWorker->pending() > 0)
	{
		double waited = 0;
		const bool due = p.apply_when_ready ? m_loopWorker->ready()
											: atKeyframe && m_loopWorker->due(m_keyframeClock, waited);
		if (waited > 0)
		{
			++m_stats.loopResultWaits;
			m_stats.loopResultWaitSeconds += waited;
			m_stats.loopResultWaitMaxSeconds = std::max(m_stats.loopResultWaitMaxSeconds, waited);
		}
		if (!due) break;
		TLoopJobResult r = m_loopWorker->take();
		m_stats.loopResultDelayMax = std::max(m_stats.loopResultDelayMax, m_keyframeClock - r.clock);
		applyLoopResult(std::move(r));
	}
	if (!atKeyframe || !newKeyframe || newest == 0) return;

	TLoopJob job;
	job.newest = newest;
	job.clock = m_keyframeClock;
	job.firstPose = std::min(m_graph.takeLowestMovedNode(), m_nodesForWorker);
	job.poses.assign(m_graph.poses().begin() + job.firstPose, m_graph.poses().end());
	for (size_t i = m_nodesForWorker; i <= newest; ++i) job.scans.push_back(&m_keyframes[i].scan);
	m_nodesForWorker = newest + 1;
	for (size_t id = m_linkWatermark; id < m_graph.numLinks(); ++id)
		m_linksForWorker.push_back(m_graph.link(id));
	m_linkWatermark = m_graph.numLinks();
	job.links = std::exchange(m_linksForWorker, {});
	job.resultsApplied = m_loopResultsApplied;
	m_loopWorker->submit(std::move(job));
	if (p.result_delay_keyframes == 0 && !p.apply_when_ready) applyLoopResult(m_loopWorker->take());
}

// A loop search's result, computed from the graph as it was at keyframe k = r.newest: its
// links are added; if it moved the map, nodes 0..k take its poses and the nodes added since
// are carried along by node k's correction (no re-registration):
//     X_i <- X'_k (+) (X_k^-1 (+) X_i),  i > k.
void CMetricMapBuilderLRGC::applyLoopResult(TLoopJobResult&& r)
{
	const size_t k = r.newest, n = m_graph.numNodes();
	if (!r.poses.empty())
	{
		const size_t at = anchor();
		const TPose2D oldK = m_graph.pose(k), oldAnchor = m_graph.pose(at);
		for (size_t i = 0; i < r.poses.size(); ++i) m_graph.setPose(r.firstMoved + i, r.poses[i]);
		const TPose2D newK = m_graph.pose(k);
		for (size_t i = k + 1; i < n; ++i)
			m_graph.setPose(i, compose(newK, between(oldK, m_graph.pose(i))));
		m_lastScanInMap = compose(m_graph.pose(at), between(oldAnchor, m_lastScanInMap));
		m_local->invalidate();
	}
	// Links added here since the job go to the worker with the next one, before these.
	for (size_t id = m_linkWatermark; id < m_graph.numLinks(); ++id)
		m_linksForWorker.push_back(m_graph.link(id));
	for (size_t i = 0; i < r.links.size(); ++i)
		if (const size_t id = m_graph.addLink(r.links[i]); !r.linkEnabled[i])
			m_graph.setLinkEnabled(id, false);
		else if (r.links[i].type == LinkType::LoopClosure)
			m_reuse->noteLoopLink(n - 1);  // the robot is tied to the map from here on
	m_linkWatermark = m_graph.numLinks();
	m_metricMapDirty = true;
	++m_loopResultsApplied;

	if (!r.closure) return;
	const TLoopClosure& closure = *r.closure;
	++m_stats.loopClosures;
	m_stats.loopClosureLinks += 1 + closure.rematchLinks;
	if (closure.optimized)
		MRPT_LOG_INFO_FMT(
			"loop closed: keyframe %zu -> %zu (score %.2f, ambiguity %.2f), %zu re-matched "
			"links, %.1f ms",
			closure.newNode, closure.oldNode, closure.score, closure.ambiguity,
			closure.rematchLinks, 1e3 * closure.seconds);
}

TLoopCloserStats CMetricMapBuilderLRGC::loopCloserStats() const
{
	const auto lock = lockMap();
	return m_loopWorker ? m_loopWorker->stats() : TLoopCloserStats{};
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

// The scan that moves the robot's anchor from keyframe a to an existing keyframe c measures
// their relative pose, as the reduced pose graph keeps a revisit's evidence (Johannsson et
// al. 2013): (a <- scan) from its registration against the window patch (in a's frame), and
// (c <- scan) from its match against c's scan, so
//     Z_ac = (a <- scan) (+) (c <- scan)^-1,  C_ac ~ C_a + R(Z_ac.phi) C_c R^T
// (the lever arm left out: the scan is within the cover radius of both). A loop link (the
// scans were taken at different times; robust in the whole-graph solves), with the loop
// links' noise floor.
void CMetricMapBuilderLRGC::linkReused(const TReusedKeyframe& c, const TRegistration& reg)
{
	const size_t a = anchor();
	const TPose2D aInMap = m_graph.pose(a);
	const TPose2D scanInA = between(aInMap, reg.scanInMap);
	const TPose2D z = compose(scanInA, inverse(c.scanInNode));
	const Eigen::Matrix3d covA = rotateCovariance(reg.cov, -aInMap.phi);  // map axes -> a's
	const Eigen::Matrix3d covC = rotateCovariance(c.cov, z.phi);  // c's axes -> a's
	m_graph.addLink(
		{a, c.node, z, linkInformation(covA + covC, m_params.loop.link_noise),
		 LinkType::LoopClosure});
	++m_stats.loopClosureLinks;
}

size_t CMetricMapBuilderLRGC::anchor() const
{
	return m_local->anchor().value_or(m_graph.numNodes() - 1);
}

bool CMetricMapBuilderLRGC::isNewKeyframe(const TPose2D& scanInMap) const
{
	const TPose2D d = between(compose(m_graph.pose(anchor()), m_anchorOffset), scanInMap);
	return translationNorm(d) >= m_params.builder.keyframe_distance_m ||
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

// The odometry link (the anchor keyframe `from` -> the new keyframe `to`): the odometry
// motion composed over the scans in between with its proportional noise (from a reused
// keyframe: its registered offset, then the odometry); where odometry was absent or
// rejected as a glitch, the registered motion with the weak constant-velocity noise, so
// the graph stays connected without the link pulling the map.
TLink CMetricMapBuilderLRGC::odometryLink(size_t from, size_t to) const
{
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
// The mapped laser's scan with its range limits applied, or null for another laser's
// (CLaserSelector counts it, and warns once when a second laser shows up unasked).
mrpt::obs::CObservation2DRangeScan::Ptr CMetricMapBuilderLRGC::acceptLaser(
	const mrpt::obs::CObservation2DRangeScan::Ptr& laser)
{
	auto mapped = m_lasers.select(laser);
	if (auto w = m_lasers.takeWarning()) warn(std::move(*w));
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

void CMetricMapBuilderLRGC::processActionObservation(
	mrpt::obs::CActionCollection& action, mrpt::obs::CSensoryFrame& observations)
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
	if (laser) processScan(laser, sf);
	else ++m_stats.ignoredObservations;
}

}  // namespace lrgc
