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

// A new probe from the next scan on; a search of the previous probe still in the worker is
// left to finish and its result dropped.
void CLocalizer::startSearch(bool wholeMap)
{
	dropSearch();
	// Kidnapped: small patches on the whole map, their attempts backing off (see the header).
	TLocalizationParams lp = m_lp;
	if (wholeMap) lp.patch_keyframes = std::min(lp.patch_keyframes, kKidnapPatchKeyframes);
	m_finder = std::make_unique<CStartFinder>(m_global, m_params, lp, wholeMap);
	m_finder->setStopToken(m_stop);
	m_finderFirstIndex = m_trajectory.size();  // the probe starts with the next scan
	m_searchWholeMap = wholeMap;
}

void CLocalizer::dropSearch()
{
	m_finder.reset();
	++m_generation;
}

void CLocalizer::serviceSearch(double stamp)
{
	if (auto location = m_worker.takeIfDue(stamp)) applySearchResult(*location, stamp);
	if (!m_finder || m_worker.busy()) return;
	auto request = m_finder->nextPatch();
	if (!request) return;
	const TSearchArea area = searchArea(request->newestInProbe);
	TGlobalSearchJob job;
	job.patch = request->points;
	job.area = area;
	job.submittedAt = stamp;
	m_inFlight = std::move(*request);
	m_inFlightGeneration = m_generation;
	m_inFlightWindow = area.halfXY;
	m_worker.submit(std::move(job));
}

// Where the next attempt looks (see the file comment). The patch is in the frame of the probe's
// keyframe `newestInProbe`; tracking carried the scan just processed (the probe's last) to
// m_pose, so that keyframe is at m_pose (+) (last^-1 (+) newest) in the map.
TSearchArea CLocalizer::searchArea(const TPose2D& newestInProbe) const
{
	if (!m_stats.started || m_searchWholeMap) return m_global.wholeMap();
	const TPose2D lastInProbe = m_finder->probe().trajectory().back().robotInMap;
	TSearchArea a;
	a.centre = compose(m_pose, between(lastInProbe, newestInProbe));
	a.halfXY =
		std::max(kMinSearchHalfXY, 3 * std::sqrt(std::max(m_driftCov(0, 0), m_driftCov(1, 1))));
	a.halfTheta = std::max(kMinSearchHalfTheta, 3 * std::sqrt(m_driftCov(2, 2)));
	return m_global.clipped(a);
}

void CLocalizer::applySearchResult(const TGlobalLocation& location, double stamp)
{
	++m_stats.globalAttempts;
	m_stats.globalSeconds += location.seconds;
	m_stats.globalModelledSeconds += location.modelledMs * 1e-3;
	const TPatchRequest request = std::move(*m_inFlight);
	m_inFlight.reset();
	if (m_inFlightGeneration != m_generation || !m_finder) return;  // its probe is gone
	const auto found = m_finder->conclude(request, location);
	if (!found)
	{
		m_stats.lastRejection = m_finder->lastRejection();
		return;
	}
	const bool starting = !m_stats.started;
	const TPose2D before = m_pose;
	adoptFinderPoses(*found);
	if (starting)
	{
		m_stats.started = true;
		m_stats.scansBeforeStart = m_stats.scans - 1;  // this scan has its pose
		MRPT_LOG_INFO_FMT("start found after %zu scans (score %.2f, ambiguity %.2f)",
						  m_stats.scans, found->score, found->ambiguity);
		record(Kind::Started, stamp, 0, m_inFlightWindow);
		return;
	}
	++m_stats.relocalizations;
	m_poorInARow = m_contradictedInARow = 0;
	const double jump = translationNorm(between(before, m_pose));
	MRPT_LOG_WARN_FMT("relocalised at t=%.3f: the pose moved %.2f m", stamp, jump);
	record(Kind::Relocalized, stamp, jump, m_inFlightWindow);
}

void CLocalizer::record(Kind kind, double stamp, double jump, double window)
{
	TLocalizationEvent e;
	e.kind = kind, e.stamp = stamp, e.pose = m_pose, e.jump_m = jump, e.window_m = window;
	m_stats.events.push_back(e);
}

// The finder's scans get their map poses: appended at the start, replacing the tracked ones
// (same timestamps) after a relocalisation.
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
	m_recentCloud.reset();
	dropSearch();
}

bool CLocalizer::track(const TScan2D& scan, mrpt::Clock::time_point t, bool& contradicted)
{
	const TMotionPrediction pred = m_predictor->predict(t);
	const TPose2D prior = compose(m_pose, pred.motion);
	const Eigen::Matrix3d priorCov = m_driftCov + rotateCovariance(pred.cov, m_pose.phi);
	TPose2D pose = prior;
	bool good = false;
	contradicted = false;
	if (referenceNear(prior, true))
	{
		TPose2D guess = between(m_refInMap, prior);
		auto m = matchReference(scan, guess);
		good = isGoodMatch(m, guess, priorCov);
		// A kept reference (track_keep_share) that fails the scan: the scan is matched, and
		// judged contradicted or not, against the keyframes near the prior themselves.
		if (!good && !m_refExact && referenceNear(prior, false))
		{
			guess = between(m_refInMap, prior);
			m = matchReference(scan, guess);
			good = isGoodMatch(m, guess, priorCov);
		}
		if (good) pose = compose(m_refInMap, m->scanInRef);
		m_lastMapGood = good && m->inlierFraction >= kKeepInlierFraction;
		// Contradicted: no match, and the scan at the prior puts walls where the map's
		// beams passed (a wrong place, not a room the map saw only from its door), for
		// every pass of the keyframes near it on its own (not a place changed between passes).
		contradicted =
			!(m && m->inlierFraction >= m_lp.min_inlier_fraction) &&
			m_ref.freeSpaceViolation(scan, guess, kContradictionMargin) >=
				kContradictionFraction &&
			m_views.contradictsEveryPass(scan, prior, m_refNodes, kContradictionMargin,
										 kContradictionFraction);
	}
	else
		m_lastMapGood = false;
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

std::optional<TScanMatch> CLocalizer::matchReference(const TScan2D& scan, const TPose2D& guess)
{
	auto m = m_trackMatcher.match(m_ref, scan, guess);
	const double limit = m_matcher.params().max_free_space_violation;
	if (!m || limit >= 1) return m;
	const double margin = CScanMatcher::freeSpaceMargin(m->residualStd);  // as the matcher's
	m->freeSpaceViolation = m_ref.freeSpaceViolation(scan, m->scanInRef, margin);
	if (refusedByFreeSpace(*m, limit, m_views, scan, compose(m_refInMap, m->scanInRef),
						   m_refNodes, margin))
		return std::nullopt;
	return m;
}

bool CLocalizer::refusedByFreeSpace(const TScanMatch& m, double limit,
									CViewContradiction& views, const TScan2D& scan,
									const TPose2D& poseInMap, const std::vector<size_t>& nodes,
									double margin)
{
	if (m.freeSpaceViolation <= limit) return false;
	return m.inlierFraction < kKeepInlierFraction || m.rmsResidual > kChangedPlaceRms_m ||
		   views.contradictsEveryPass(scan, poseInMap, nodes, margin, limit);
}

std::optional<TPose2D> CLocalizer::matchRecent(const TScan2D& scan, const TPose2D& prior)
{
	if (m_recent.empty()) return std::nullopt;
	const TPose2D refInMap = m_recent.back().second;
	if (!m_recentCloud)  // built once per change of m_recent
	{
		std::vector<TScan2D> scans;
		std::vector<TPose2D> inRef;
		for (const auto& [s, p] : m_recent)
			scans.push_back(s), inRef.push_back(between(refInMap, p));
		m_recentCloud = CReferenceCloud::fromScans(scans, inRef, m_matcher.params());
	}
	const auto m = m_matcher.match(*m_recentCloud, scan, between(refInMap, prior));
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
	m_recentCloud.reset();
}

bool CLocalizer::stillCovers(const std::vector<size_t>& current,
							 const std::vector<size_t>& near, size_t nearest, double share)
{
	// Both sorted. The reference must hold the nearest keyframe (the scan is matched where it
	// is best seen) and share * |near| of the keyframes near the pose now.
	if (current.empty() || !std::binary_search(current.begin(), current.end(), nearest))
		return false;
	size_t common = 0;
	for (const size_t i : near)
		common += std::binary_search(current.begin(), current.end(), i) ? 1 : 0;
	return static_cast<double>(common) >= share * static_cast<double>(near.size());
}

bool CLocalizer::isGoodMatch(const std::optional<TScanMatch>& m, const TPose2D& guess,
							 const Eigen::Matrix3d& priorCov) const
{
	// The map's scans were taken at other times (people, doors) and its passes agree to
	// about the loop links' noise floor, not to the match covariance alone.
	return m && m->inlierFraction >= m_lp.min_inlier_fraction &&
		   disagreementChi2(guess, m->scanInRef,
							rotateCovariance(priorCov, -m_refInMap.phi) + m->cov +
								m_params.loop.link_noise.floorCovariance()) <= m_lp.gate_chi2;
}

bool CLocalizer::referenceNear(const TPose2D& pose, bool mayKeep)
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
	m_refExact = nodes == m_refNodes;
	if (m_refExact || (mayKeep && m_lastMapGood &&
					   stillCovers(m_refNodes, nodes, nearest, m_lp.track_keep_share)))
		return true;
	m_refExact = true;
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
