/* CLocalizer (Localizer.h): construction, the observations in, each scan's way through tracking
 * and the loss and kidnap rules (trackAndWatch), and the events recorded. Tracking:
 * Localizer_tracking.cpp; the start and relocalisation searches: Localizer_search.cpp. */
#include <lrgc/localization/Localizer.h>

#include <lrgc/common/se2.h>
#include <lrgc/local_registration/MotionPredictor.h>
#include <lrgc/scan_matching/ScanGeometry.h>

#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>

#include <algorithm>
#include <cmath>

namespace lrgc
{
using mrpt::math::TPose2D;
using Kind = TLocalizationEvent::Kind;

const char* TLocalizationEvent::name() const
{
	switch (kind)
	{
		case Kind::Started:
			return "started";
		case Kind::Lost:
			return "lost";
		case Kind::Kidnapped:
			return "kidnapped";
		case Kind::Relocalized:
			return "relocalized";
		case Kind::RecoveredByTracking:
			return "recovered_by_tracking";
	}
	return "?";
}

// The global searches' correlator: [PatchCorrelator] at [Localization] search_resolution_m.
static TPatchCorrelatorParams searchCorrelator(TPatchCorrelatorParams p,
											   const TLocalizationParams& localization)
{
	p.resolution_m = localization.search_resolution_m;
	p.validate();
	return p;
}

CLocalizer::CLocalizer(const CPoseGraph& map, const TKeyframes& keyframes,
					   const TLRGCParams& params, const TLocalizationParams& localization,
					   bool backgroundSearch)
	: m_map(map),
	  m_keyframes(keyframes),
	  m_params(params),
	  m_lp(localization),
	  m_views(m_map, m_keyframes, params.matcher),
	  m_global(map, keyframes, searchCorrelator(params.correlator, localization)),
	  m_predictor(std::make_unique<CMotionPredictor>(params.motion)),
	  m_worker(m_global, localization.search_budget_ms_per_s, backgroundSearch)
{
	setLoggerName("CLocalizer");
	// As local registration: people walk through the new scans, so the map may look emptier
	// there than the scan says; the relaxed free-space limit keeps good matches.
	TScanMatcherParams mp = params.matcher;
	mp.max_free_space_violation = params.local.max_free_space_violation;
	m_matcher = CScanMatcher(mp);
	mp.max_free_space_violation = 1;  // checked pass by pass instead (matchReference)
	m_trackMatcher = CScanMatcher(mp);
	m_finder = std::make_unique<CStartFinder>(m_global, m_params, m_lp);
}

CLocalizer::~CLocalizer() = default;

void CLocalizer::setStopToken(const CStopToken& stop)
{
	m_stop = stop;
	m_global.setStopToken(stop);
	m_matcher.setStopToken(stop);
	m_trackMatcher.setStopToken(stop);
	if (m_finder) m_finder->setStopToken(stop);
}

const TLocalizerStats& CLocalizer::stats() const
{
	m_stats.localizedScans = m_posesTaken + m_trajectory.size();
	m_stats.replayWaitSeconds = m_worker.waitedSeconds();
	m_stats.replayWaitMaxSeconds = m_worker.longestWaitSeconds();
	m_stats.searchesOnTrackingThread = m_worker.searchesOnCallerThread();
	return m_stats;
}

TTrajectory CLocalizer::takeSettledPoses()
{
	const size_t settled =
		m_finder && m_stats.started ? m_finderFirstIndex : m_trajectory.size();
	TTrajectory out(m_trajectory.begin(), m_trajectory.begin() + settled);
	m_trajectory.erase(m_trajectory.begin(), m_trajectory.begin() + settled);
	m_finderFirstIndex -= std::min(m_finderFirstIndex, settled);
	m_posesTaken += settled;
	return out;
}

void CLocalizer::processObservation(const mrpt::obs::CObservation::Ptr& obs)
{
	ASSERT_(obs);
	m_lastWait = 0;
	if (auto odo = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(obs))
	{
		m_predictor->addOdometryAbsolute(odo->odometry.asTPose());
		if (m_finder) m_finder->probe().processObservation(obs);
	}
	else if (auto laser = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs))
	{
		if (m_laserLabel.empty()) m_laserLabel = laser->sensorLabel;
		if (laser->sensorLabel != m_laserLabel) return;
		if (m_finder) m_finder->probe().processObservation(obs);
		processScan(laser);
	}
}

void CLocalizer::processActionObservation(mrpt::obs::CActionCollection& action,
										  mrpt::obs::CSensoryFrame& observations)
{
	m_lastWait = 0;
	if (auto odo = action.getBestMovementEstimation(); odo && odo->poseChange)
		m_predictor->addOdometryIncrement(odo->poseChange->getMeanVal().asTPose());
	mrpt::obs::CObservation2DRangeScan::Ptr laser;
	for (const auto& o : observations)
		if (auto l = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(o))
		{
			if (m_laserLabel.empty()) m_laserLabel = l->sensorLabel;
			if (l->sensorLabel == m_laserLabel && !laser) laser = l;
		}
		else if (auto od = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(o))
			m_predictor->addOdometryAbsolute(od->odometry.asTPose());
	if (m_finder) m_finder->probe().processActionObservation(action, observations);
	if (laser) processScan(laser);
}

void CLocalizer::processScan(const mrpt::obs::CObservation2DRangeScan::Ptr& observed)
{
	// Through the door every scan takes (ScanGeometry.h): unusable geometry dropped.
	const auto laser = checkScanGeometry(observed).scan;
	if (!laser) return;
	const TScan2D scan = scanFromObservation(*laser);
	if (scan.points.size() < m_params.builder.min_scan_points) return;  // as the builder
	++m_stats.scans;
	const auto t = laser->timestamp;
	m_lastScanTime = t;
	if (m_worker.busy()) ++m_stats.scansDuringSearches;
	// The log's clock for the search schedule: never backwards (logs have backward stamps).
	m_logClock = std::max(m_logClock, mrpt::Clock::toDouble(t));
	if (m_stats.started)
		trackAndWatch(scan, t);  // 2. and 3.: never waits for a search
	else
	{
		// 1. Start: the finder's probe has this scan; no map pose yet.
		m_predictor->commitScan(t, TPose2D(0, 0, 0));
		++m_stats.scansBeforeStart;
	}
	const double waitedBefore = m_worker.waitedSeconds();
	serviceSearch(m_logClock);
	m_lastWait = m_worker.waitedSeconds() - waitedBefore;
}

void CLocalizer::trackAndWatch(const TScan2D& scan, mrpt::Clock::time_point t)
{
	bool contradicted = false;
	const double stamp = mrpt::Clock::toDouble(t);
	if (track(scan, t, contradicted))
	{
		m_poorInARow = m_contradictedInARow = 0;
		if (m_finder)  // lost, but the map matches again
		{
			++m_stats.recoveredByTracking;
			record(Kind::RecoveredByTracking, stamp);
			dropSearch();
		}
		return;
	}
	++m_poorInARow;
	m_contradictedInARow = contradicted ? m_contradictedInARow + 1 : 0;
	// 3. Lost: relocalise near the carried pose; kidnapped: on the whole map.
	if (m_contradictedInARow >= m_lp.kidnap_after && !(m_finder && m_searchWholeMap))
	{
		++m_stats.kidnapEvents;
		MRPT_LOG_WARN_FMT(
			"kidnapped at t=%.3f: %zu scans in a row contradict the map: "
			"relocalising on the whole map",
			stamp, m_contradictedInARow);
		record(Kind::Kidnapped, stamp);
		startSearch(true);
	}
	else if (!m_finder && m_poorInARow >= m_lp.lost_after)
	{
		++m_stats.lostEvents;
		MRPT_LOG_WARN_FMT("lost at t=%.3f after %zu poor matches: relocalising", stamp,
						  m_poorInARow);
		record(Kind::Lost, stamp);
		startSearch(false);
	}
}

void CLocalizer::record(Kind kind, double stamp, double jump, double window)
{
	TLocalizationEvent e;
	e.kind = kind, e.stamp = stamp, e.pose = m_pose, e.jump_m = jump, e.window_m = window;
	m_stats.events.push_back(e);
}

}  // namespace lrgc
