/* CLocalizer's global searches (Localizer.h, steps 1 and 3): the start and every relocalisation
 * are a CStartFinder probe whose patches CGlobalSearchWorker correlates beside tracking, within
 * searchArea; a patch that passes the filters gives the probe's scans their map poses
 * (adoptFinderPoses). Tracking: Localizer_tracking.cpp; observations and events: Localizer.cpp.
 */
#include <lrgc/localization/Localizer.h>

#include <lrgc/common/se2.h>

#include <algorithm>
#include <cmath>

namespace lrgc
{
using mrpt::math::TPose2D;
using Kind = TLocalizationEvent::Kind;

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
	if (!probeMatchesMap(*found))
	{
		++m_stats.globalRefusedByScan;
		m_stats.lastRejection =
			"a scan of the patch does not match the map where the patch fits";
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

// The paper's filters judge the patch's correlation with the map's blurred grid, cell by cell
// (0.10 m cells for a search, [Localization] search_resolution_m). A patch of corridors can
// pass them where the map's corridors run alike but its scans do not fit: SENA's scans seen
// in a mirror (y -> -y) were placed after 149 scans, then every tracked scan after that
// matched poorly and five in a row contradicted the map (kidnapped). So the pose is taken only
// if every keyframe of the accepted patch, placed by it, makes the match tracking would call
// good (isGoodMatch: min_inlier_fraction of the scan, within gate_chi2 of the pose under the
// correlation's covariance, the match's and the map's floor). Every one, not most: ACES's
// corridors, localised on MIT-CSAIL's map, were placed after 6848 scans by a patch of 32
// keyframes of which 26 matched well there (four kidnaps followed); its own logs' starts
// match with all (Intel 16 of 16, ACES 1 of 1, MIT-CSAIL 1 of 1, Killian 16 of 16). A
// keyframe with no map keyframe within track_radius_m has nothing to be checked against.
bool CLocalizer::probeMatchesMap(const TStartFound& found)
{
	const CMetricMapBuilderLRGC& probe = m_finder->probe();
	const size_t n = probe.graph().numNodes();
	const size_t count = std::min(n, std::max<size_t>(1, found.patchKeyframes));
	for (size_t k = n - count; k < n; ++k)  // the newest last: the reference stays near it
	{
		const TPose2D poseInMap = compose(found.probeInMap, probe.graph().pose(k));
		if (!referenceNear(poseInMap, false)) continue;  // nothing to check it against
		const TPose2D guess = between(m_refInMap, poseInMap);
		if (!isGoodMatch(matchReference(probe.keyframes()[k].scan, guess), guess, found.cov))
			return false;
	}
	return true;
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

}  // namespace lrgc
