/* CLocalizer's tracking (Localizer.h, step 2): each scan matched against the map's keyframes
 * near its odometry prediction (referenceNear, matchReference, with the free-space check asked
 * pass by pass: refusedByFreeSpace), else against the log's own recent scans (matchRecent).
 * Searches: Localizer_search.cpp; observations and events: Localizer.cpp. */
#include <lrgc/localization/Localizer.h>

#include <lrgc/common/se2.h>
#include <lrgc/local_registration/MotionPredictor.h>

#include <algorithm>
#include <cmath>

namespace lrgc
{
using mrpt::math::TPose2D;

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
	// Distances in the map frame: |t(X_i^-1 (+) X)| = |t(X) - t(X_i)|, no rotation needed; the
	// squared distance orders the nodes as the distance does (this runs over every map node
	// for every scan: Killian's 5279).
	std::vector<std::pair<double, size_t>> near;
	const double r2 = m_lp.track_radius_m * m_lp.track_radius_m;
	for (size_t i = 0; i < m_map.numNodes(); ++i)
	{
		const double dx = pose.x - m_map.pose(i).x, dy = pose.y - m_map.pose(i).y;
		if (const double d2 = dx * dx + dy * dy; d2 <= r2) near.emplace_back(d2, i);
	}
	if (near.empty()) return false;
	std::sort(near.begin(), near.end());
	near.resize(std::min(near.size(), m_lp.track_max_keyframes));
	std::vector<size_t> nodes;
	for (const auto& [d2, i] : near) nodes.push_back(i);
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
