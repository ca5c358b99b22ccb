#include <lrgc/localization/Localizer.h>

#include <lrgc/common/se2.h>
#include <lrgc/local_registration/MotionPredictor.h>
#include <lrgc/scan_matching/ScanGeometry.h>

#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>

#include <algorithm>

namespace lrgc
{
using mrpt::math::TPose2D;

CLocalizer::CLocalizer(const CPoseGraph& map, const TKeyframes& keyframes,
					   const TLRGCParams& params, const TLocalizationParams& localization)
	: m_map(map),
	  m_keyframes(keyframes),
	  m_params(params),
	  m_lp(localization),
	  m_global(map, keyframes, params.correlator),
	  m_predictor(std::make_unique<CMotionPredictor>(params.motion))
{
	setLoggerName("CLocalizer");
	// As local registration: people walk through the new scans, so the map may look emptier
	// there than the scan says; the relaxed free-space limit keeps good matches.
	TScanMatcherParams mp = params.matcher;
	mp.max_free_space_violation = params.local.max_free_space_violation;
	m_matcher = CScanMatcher(mp);
	m_finder = std::make_unique<CStartFinder>(m_global, m_params, m_lp);
}

CLocalizer::~CLocalizer() = default;

void CLocalizer::setStopToken(const CStopToken& stop)
{
	m_stop = stop;
	m_global.setStopToken(stop);
	m_matcher.setStopToken(stop);
	if (m_finder) m_finder->setStopToken(stop);
}

const TLocalizerStats& CLocalizer::stats() const
{
	m_stats.localizedScans = m_trajectory.size();
	m_stats.globalAttempts = m_finderAttemptsBefore + (m_finder ? m_finder->attempts() : 0);
	m_stats.globalSeconds = m_finderSecondsBefore + (m_finder ? m_finder->secondsSpent() : 0);
	if (m_finder && !m_finder->lastRejection().empty())
		m_stats.lastRejection = m_finder->lastRejection();
	return m_stats;
}

void CLocalizer::processObservation(const mrpt::obs::CObservation::Ptr& obs)
{
	ASSERT_(obs);
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
	if (!m_stats.started)
	{
		// 1. Start: the finder's probe has this scan; no map pose yet.
		m_predictor->commitScan(t, TPose2D(0, 0, 0));
		if (const auto found = m_finder->tryLocate())
		{
			adoptFinderPoses(*found);
			m_stats.started = true;
			MRPT_LOG_INFO_FMT("start found after %zu scans (score %.2f, ambiguity %.2f)",
							  m_stats.scans, found->score, found->ambiguity);
		}
		else
			++m_stats.scansBeforeStart;
		return;
	}
	// 2. Tracking.
	if (track(scan, t))
	{
		m_poorInARow = 0;
		if (m_finder)  // lost, but the map matches again
		{
			++m_stats.recoveredByTracking;
			m_finderAttemptsBefore += m_finder->attempts();
			m_finderSecondsBefore += m_finder->secondsSpent();
			m_finder.reset();
		}
		return;
	}
	// 3. Lost: relocalise.
	if (!m_finder)
	{
		if (++m_poorInARow < m_lp.lost_after) return;
		++m_stats.lostEvents;
		MRPT_LOG_WARN_FMT("lost at t=%.3f after %zu poor matches: relocalising",
						  mrpt::Clock::toDouble(t), m_poorInARow);
		m_finder = std::make_unique<CStartFinder>(m_global, m_params, m_lp);
		m_finder->setStopToken(m_stop);
		m_finderFirstIndex = m_trajectory.size();  // the probe starts with the next scan
		return;
	}
	if (const auto found = m_finder->tryLocate())
	{
		adoptFinderPoses(*found);
		++m_stats.relocalizations;
		m_poorInARow = 0;
	}
}

// The finder's scans get their map poses: appended at the start, replacing the odometry-
// carried ones (same timestamps) after a relocalisation.
void CLocalizer::adoptFinderPoses(const TStartFound& found)
{
	const TTrajectory probe = m_finder->probe().trajectory();
	if (!m_stats.started)
		for (const auto& p : probe)
			m_trajectory.push_back({p.timestamp, compose(found.probeInMap, p.robotInMap)});
	else
	{
		size_t k = m_finderFirstIndex;
		for (const auto& p : probe)
		{
			while (k < m_trajectory.size() && m_trajectory[k].timestamp != p.timestamp) ++k;
			if (k == m_trajectory.size()) break;
			m_trajectory[k].robotInMap = compose(found.probeInMap, p.robotInMap);
		}
	}
	if (!probe.empty()) m_pose = compose(found.probeInMap, probe.back().robotInMap);
	m_driftCov = found.cov;
	m_refNodes.clear();
	m_recent.clear();  // placed where the robot was thought to be
	m_finderAttemptsBefore += m_finder->attempts();
	m_finderSecondsBefore += m_finder->secondsSpent();
	m_finder.reset();
}

bool CLocalizer::track(const TScan2D& scan, mrpt::Clock::time_point t)
{
	const TMotionPrediction pred = m_predictor->predict(t);
	const TPose2D prior = compose(m_pose, pred.motion);
	const Eigen::Matrix3d priorCov = m_driftCov + rotateCovariance(pred.cov, m_pose.phi);
	TPose2D pose = prior;
	bool good = false;
	if (referenceNear(prior))
	{
		const TPose2D guess = between(m_refInMap, prior);
		const auto m = m_matcher.match(m_ref, scan, guess);
		// The map's scans were taken at other times (people, doors) and its passes agree to
		// about the loop links' noise floor, not to the match covariance alone.
		good =
			m && m->inlierFraction >= m_lp.min_inlier_fraction &&
			disagreementChi2(guess, m->scanInRef,
							 rotateCovariance(priorCov, -m_refInMap.phi) + m->cov +
								 m_params.loop.link_noise.floorCovariance()) <= m_lp.gate_chi2;
		if (good) pose = compose(m_refInMap, m->scanInRef);
	}
	if (!good)
		if (const auto local = matchRecent(scan, prior)) pose = *local, ++m_stats.recentMatches;
	m_driftCov = good ? Eigen::Matrix3d::Zero() : priorCov;
	m_predictor->commitScan(t, between(m_pose, pose));
	m_pose = pose;
	m_trajectory.push_back({t, pose});
	keepRecent(scan, pose);
	++(good ? m_stats.goodMatches : m_stats.poorMatches);
	return good;
}

std::optional<TPose2D> CLocalizer::matchRecent(const TScan2D& scan, const TPose2D& prior) const
{
	if (m_recent.empty()) return std::nullopt;
	const TPose2D refInMap = m_recent.back().second;
	std::vector<TScan2D> scans;
	std::vector<TPose2D> inRef;
	for (const auto& [s, p] : m_recent)
		scans.push_back(s), inRef.push_back(between(refInMap, p));
	const auto m = m_matcher.match(CReferenceCloud::fromScans(scans, inRef, m_matcher.params()),
								   scan, between(refInMap, prior));
	if (!m || m->inlierFraction < m_params.local.min_link_inlier_fraction) return std::nullopt;
	return compose(refInMap, m->scanInRef);
}

void CLocalizer::keepRecent(const TScan2D& scan, const TPose2D& pose)
{
	if (!m_recent.empty())
	{
		const TPose2D d = between(m_recent.back().second, pose);
		if (translationNorm(d) < m_params.builder.keyframe_distance_m &&
			std::abs(d.phi) < m_params.builder.keyframe_angle)
			return;
	}
	m_recent.emplace_back(scan, pose);
	if (m_recent.size() > m_params.local.window_size) m_recent.pop_front();
}

bool CLocalizer::referenceNear(const TPose2D& pose)
{
	std::vector<std::pair<double, size_t>> near;
	for (size_t i = 0; i < m_map.numNodes(); ++i)
		if (const double d = translationNorm(between(m_map.pose(i), pose));
			d <= m_lp.track_radius_m)
			near.emplace_back(d, i);
	if (near.empty()) return false;
	std::sort(near.begin(), near.end());
	near.resize(std::min(near.size(), m_lp.track_max_keyframes));
	std::vector<size_t> nodes;
	for (const auto& [d, i] : near) nodes.push_back(i);
	const size_t nearest = nodes.front();
	std::sort(nodes.begin(), nodes.end());
	if (nodes == m_refNodes) return true;
	m_refNodes = nodes;
	m_refInMap = m_map.pose(nearest);
	std::vector<TScan2D> scans;
	std::vector<TPose2D> inRef;
	for (const size_t i : nodes)
	{
		scans.push_back(m_keyframes[i].scan);
		inRef.push_back(between(m_refInMap, m_map.pose(i)));
	}
	m_ref = CReferenceCloud::fromScans(scans, inRef, m_matcher.params());
	return true;
}

}  // namespace lrgc
