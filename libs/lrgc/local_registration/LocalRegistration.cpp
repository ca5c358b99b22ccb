#include <lrgc/local_registration/LocalRegistration.h>

#include <lrgc/common/params_io.h>
#include <lrgc/common/se2.h>

#include <mrpt/config/CConfigFileBase.h>

#include <Eigen/Dense>
#include <algorithm>

namespace lrgc
{
CLocalRegistration::CLocalRegistration(
	const TLocalRegistrationParams& p, const TScanMatcherParams& matcher,
	const TPoseGraphOptimizerParams& optimizer)
	: m_params(p), m_matcherParams(matcher), m_optimizer(optimizer)
{
	// [LocalRegistration] max_free_space_violation (0.3) replaces [ScanMatcher]'s (0.15) for
	// every match of this stage (scan to window, pairwise): with an odometry prior a wrong
	// match is unlikely, and people and glass in the window's scans would make the strict
	// value reject good matches. Loop closing and revisits keep [ScanMatcher]'s.
	m_matcherParams.maxFreeSpaceViolation = p.max_free_space_violation;
	m_matcher = CScanMatcher(m_matcherParams);
}

void CLocalRegistration::enterKeyframe(size_t node, bool reused, const CPoseGraph& graph)
{
	if (const auto it = std::find(m_window.begin(), m_window.end(), node); it != m_window.end())
		m_window.erase(it);
	m_window.push_back(node);
	while (m_window.size() > m_params.window_size) m_window.pop_front();
	if (reused) m_firstFree = graph.numNodes();
	m_cloudNewest.reset();
}

const CReferenceCloud& CLocalRegistration::windowCloud(
	const CPoseGraph& graph, const TKeyframes& keyframes)
{
	const size_t newest = m_window.back();
	if (m_cloudNewest == newest) return m_cloud;
	// The patch: every window scan with its pose in the newest keyframe's frame,
	// (newest <- node); the cloud keeps their range images for the free-space check.
	const TPose2D newestInMap = graph.pose(newest);
	std::vector<TScan2D> scans;
	std::vector<TPose2D> scansInNewest;
	for (const size_t node : m_window)
	{
		scans.push_back(keyframes[node].scan);
		scansInNewest.push_back(between(newestInMap, graph.pose(node)));
	}
	m_cloud = CReferenceCloud::fromScans(scans, scansInNewest, m_matcherParams);
	m_cloudNewest = newest;
	return m_cloud;
}

const CReferenceCloud& CLocalRegistration::keyframeCloud(size_t node, const TKeyframes& keyframes)
{
	for (const auto& [n, cloud] : m_keyframeClouds)
		if (n == node) return cloud;
	if (m_keyframeClouds.size() >= m_params.window_size) m_keyframeClouds.pop_front();
	m_keyframeClouds.emplace_back(node, CReferenceCloud::fromScan(keyframes[node].scan, m_matcherParams));
	return m_keyframeClouds.back().second;
}

TRegistration CLocalRegistration::registerScan(
	const CPoseGraph& graph, const TKeyframes& keyframes, const TScan2D& scan,
	const mrpt::math::TPose2D& priorInMap, const TMotionPrediction& prediction)
{
	const Eigen::Matrix3d& priorCov = prediction.cov;
	TRegistration reg{priorInMap, priorCov, false, false};
	m_lastPatchMatch.reset();
	if (m_window.empty()) return reg;  // no keyframe of this session yet
	const CReferenceCloud& cloud = windowCloud(graph, keyframes);
	const TPose2D newestInMap = graph.pose(*m_cloudNewest);
	const TPose2D guess = between(newestInMap, priorInMap);

	// Squared Mahalanobis distance between the prior and a match, 3 dof.
	auto disagreement = [&](const TScanMatch& m) {
		return disagreementChi2(guess, m.scanInRef, priorCov + m.cov);
	};
	std::optional<TScanMatch> match = m_matcher.match(cloud, scan, guess);
	const bool disagrees = match && disagreement(*match) > m_params.glitch_gate_chi2;
	// A pause in the scans or a large predicted turn, and the plain match failed or
	// contradicts the prior: the odometry may lag or jump, so the wide search decides and
	// may overrule the prior, but only with evidence an aliased scene cannot fake (matchWide:
	// a clear majority of the scan matched, a clear lead over every other heading and over
	// the prior's own optimum). A doubtful case keeps the prior, not a contradicting match.
	const bool suspect = std::abs(prediction.motion.phi) > m_params.glitch_min_turn ||
		prediction.stepSeconds > m_params.glitch_min_gap;
	if (suspect && (!match || disagrees) && m_params.wide_search_angle > 0)
	{
		match = m_matcher.matchWide(cloud, scan, guess, m_params.wide_search_angle);
		reg.wideSearch = match.has_value();
	}
	// Wheels that did not turn at all are the one odometry reading to trust over a match
	// that moves the robot: such a match is a wrong fit (people walking by a robot that
	// stands still, a rotationally ambiguous place); keep the prior.
	else if (disagrees && translationNorm(prediction.motion) < 1e-3 &&
			 std::abs(prediction.motion.phi) < 1e-3)
		match.reset();
	if (!match) return reg;

	reg.matched = true;
	// Only with an odometry prior: laser alone, the patch link let a robot standing at the
	// start of Intel slide 0.6 m per 20 scans (laser-only relation error 0.44 -> 1.48 m).
	if (prediction.fromOdometry)
		m_lastPatchMatch = TPatchMatch{*m_cloudNewest, match->scanInRef, match->cov};
	reg.odometryRejected = disagreement(*match) > m_params.glitch_gate_chi2;
	reg.scanInMap = compose(newestInMap, match->scanInRef);
	reg.cov = rotateCovariance(match->cov, newestInMap.phi);  // newest keyframe's axes -> map's
	return reg;
}

size_t CLocalRegistration::linkAndOptimize(
	CPoseGraph& graph, const TKeyframes& keyframes, const TLink& odometryLink)
{
	const size_t newNode = odometryLink.to;
	ASSERT_(!m_window.empty() && m_window.back() == newNode);
	graph.addLink(odometryLink);
	const std::vector<size_t> window(m_window.begin(), m_window.end());
	// Pairwise matches of the new scan against up to max_pairwise_links window scans, the
	// previous anchor first, then spread evenly back over the window (Lu & Milios' links).
	const size_t older = window.size() - 1;  // window nodes other than the new one
	const size_t links = std::min(m_params.max_pairwise_links, older);
	size_t added = 0;
	// Scan to map: the keyframe's registration against the window patch, in the frame of
	// the patch's reference node (the previous anchor). Without it (the patch match failed)
	// the pairwise links keep their full weight: they are all the scans say then.
	double pairwiseWeight = 1.0;
	if (m_params.patch_link && m_lastPatchMatch && m_lastPatchMatch->node == odometryLink.from)
	{
		pairwiseWeight = m_params.pairwise_link_weight;
		graph.addLink(
			{m_lastPatchMatch->node, newNode, m_lastPatchMatch->scanInNode,
			 linkInformation(m_lastPatchMatch->cov, m_params.patch_link_noise),
			 LinkType::ScanMatch});
		++added;
	}
	m_lastPatchMatch.reset();
	for (size_t l = 0; l < links; ++l)
	{
		const size_t node = window[older - 1 - (l * older) / links];
		const TPose2D guess = between(graph.pose(node), graph.pose(newNode));
		const auto m = m_matcher.match(keyframeCloud(node, keyframes), keyframes[newNode].scan, guess);
		if (!m || m->inlierFraction < m_params.min_link_inliers) continue;
		graph.addLink(
			{node, newNode, m->scanInRef,
			 linkInformation(m->cov, m_params.link_noise, double(links) / pairwiseWeight),
			 LinkType::ScanMatch});
		++added;
	}
	// Node 0 anchors the map frame (gauge): it never moves; nor do keyframes the robot came
	// back to (the map's), nor any node older than the last of those.
	std::vector<size_t> freeNodes;
	for (const size_t node : window)
		if (node != 0 && node >= m_firstFree) freeNodes.push_back(node);
	if (!freeNodes.empty()) m_optimizer.optimizeSubset(graph, freeNodes);
	m_cloudNewest.reset();  // window poses moved
	return added;
}

}  // namespace lrgc
