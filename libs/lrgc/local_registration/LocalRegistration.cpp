#include <lrgc/local_registration/LocalRegistration.h>

#include <lrgc/common/params_io.h>
#include <lrgc/common/se2.h>

#include <mrpt/config/CConfigFileBase.h>

#include <Eigen/Dense>

namespace lrgc
{
void TLocalRegistrationParams::loadFromConfigFile(
	const mrpt::config::CConfigFileBase& c, const std::string& s)
{
	rejectUnknownKeys(TLocalRegistrationParams(), c, s);
	window_size = c.read_uint64_t(s, "window_size", window_size);
	max_pairwise_links = c.read_uint64_t(s, "max_pairwise_links", max_pairwise_links);
	min_link_inliers = c.read_double(s, "min_link_inliers", min_link_inliers);
	glitch_gate_chi2 = c.read_double(s, "glitch_gate_chi2", glitch_gate_chi2);
	wide_search_angle = mrpt::DEG2RAD(
		c.read_double(s, "wide_search_angle_deg", mrpt::RAD2DEG(wide_search_angle)));
	glitch_min_turn =
		mrpt::DEG2RAD(c.read_double(s, "glitch_min_turn_deg", mrpt::RAD2DEG(glitch_min_turn)));
	glitch_min_gap = c.read_double(s, "glitch_min_gap", glitch_min_gap);
	requireParam(glitch_min_gap > 0, s, "glitch_min_gap", "must be > 0");
	max_free_space_violation =
		c.read_double(s, "max_free_space_violation", max_free_space_violation);
	requireParam(
		max_free_space_violation >= 0 && max_free_space_violation <= 1, s,
		"max_free_space_violation", "must be in [0, 1]");
	requireParam(glitch_min_turn >= 0, s, "glitch_min_turn_deg", "must be >= 0");
	link_noise.load(c, s, "");
	requireParam(window_size >= 2 && window_size <= 100, s, "window_size", "must be in [2, 100]");
	requireParam(
		max_pairwise_links >= 1 && max_pairwise_links < window_size, s, "max_pairwise_links",
		"must be in [1, window_size - 1]");
	requireParam(
		min_link_inliers > 0 && min_link_inliers <= 1, s, "min_link_inliers", "must be in (0, 1]");
	requireParam(glitch_gate_chi2 > 0, s, "glitch_gate_chi2", "must be > 0");
	patch_link = c.read_bool(s, "patch_link", patch_link);
	patch_link_noise.load(c, s, "patch_");
	pairwise_link_weight = c.read_double(s, "pairwise_link_weight", pairwise_link_weight);
	requireParam(
		pairwise_link_weight > 0 && pairwise_link_weight <= 1, s, "pairwise_link_weight",
		"must be in (0, 1]");
	requireParam(
		wide_search_angle >= 0 && wide_search_angle <= M_PI, s, "wide_search_angle_deg",
		"must be in [0, 180]");
}

void TLocalRegistrationParams::saveToConfigFile(
	mrpt::config::CConfigFileBase& c, const std::string& s) const
{
	const int np = mrpt::config::MRPT_SAVE_NAME_PADDING(), vp = mrpt::config::MRPT_SAVE_VALUE_PADDING();
	c.write(s, "window_size", uint64_t(window_size), np, vp, "K: keyframes registered together (paper: K >= 7)");
	c.write(s, "max_pairwise_links", uint64_t(max_pairwise_links), np, vp, "Pairwise scan-match links per new keyframe, spread over the window");
	c.write(s, "min_link_inliers", min_link_inliers, np, vp, "Min fraction of matched points for a pairwise scan-match link");
	c.write(s, "glitch_gate_chi2", glitch_gate_chi2, np, vp, "[chi2, 3 dof] Odometry/match disagreement that triggers the wide search");
	link_noise.save(c, s, "", "every pairwise scan-match link (real-scan errors the matcher cannot see)");
	c.write(s, "wide_search_angle_deg", mrpt::RAD2DEG(wide_search_angle), np, vp, "[deg] Half-width of the rotational search after an odometry glitch");
	c.write(s, "glitch_min_turn_deg", mrpt::RAD2DEG(glitch_min_turn), np, vp, "[deg] A predicted step turning more than this is suspect: wide search if the match fails");
	c.write(s, "glitch_min_gap", glitch_min_gap, np, vp, "[s] A step after a longer pause in the scans is suspect too");
	c.write(s, "max_free_space_violation", max_free_space_violation, np, vp, "Local matches: tolerated fraction of points where the window saw free space");
	c.write(s, "patch_link", patch_link, np, vp, "Link each keyframe to the previous one by its match against the window patch (scan to map)");
	patch_link_noise.save(c, s, "patch_", "the patch link");
	c.write(s, "pairwise_link_weight", pairwise_link_weight, np, vp, "Pairwise (scan to scan) links' information is scaled by this, after the split among them");
}

CLocalRegistration::CLocalRegistration(
	const TLocalRegistrationParams& p, const TScanMatcherParams& matcher,
	const TPoseGraphOptimizerParams& optimizer)
	: m_params(p), m_matcherParams(matcher), m_optimizer(optimizer)
{
	m_matcherParams.maxFreeSpaceViolation = p.max_free_space_violation;
	m_matcher = CScanMatcher(m_matcherParams);
}

std::vector<size_t> CLocalRegistration::windowNodes(const CPoseGraph& graph) const
{
	const size_t n = graph.numNodes();
	const size_t first = n > m_params.window_size ? n - m_params.window_size : 0;
	std::vector<size_t> nodes;
	for (size_t i = first; i < n; ++i) nodes.push_back(i);
	return nodes;
}

const CReferenceCloud& CLocalRegistration::windowCloud(
	const CPoseGraph& graph, const TKeyframes& keyframes)
{
	const size_t newest = graph.numNodes() - 1;
	if (m_cloudNewest == newest) return m_cloud;
	// The patch: every window scan with its pose in the newest keyframe's frame,
	// (newest <- node); the cloud keeps their range images for the free-space check.
	const TPose2D newestInMap = graph.pose(newest);
	std::vector<TScan2D> scans;
	std::vector<TPose2D> scansInNewest;
	for (const size_t node : windowNodes(graph))
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
	if (graph.numNodes() == 0) return reg;
	const CReferenceCloud& cloud = windowCloud(graph, keyframes);
	const TPose2D newestInMap = graph.pose(*m_cloudNewest);
	const TPose2D guess = between(newestInMap, priorInMap);

	// Squared Mahalanobis distance between the prior and a match, 3 dof.
	auto disagreement = [&](const TScanMatch& m) {
		Eigen::Vector3d d = toVector(between(guess, m.scanInRef));
		return double(d.transpose() * (priorCov + m.cov).inverse() * d);
	};
	std::optional<TScanMatch> match = m_matcher.match(cloud, scan, guess);
	const bool disagrees = match && disagreement(*match) > m_params.glitch_gate_chi2;
	// A pause in the scans or a large predicted turn, and the plain match failed or
	// contradicts the prior: the odometry may lag or jump, so the wide search decides (it
	// has its own ambiguity check) and may overrule the prior.
	const bool suspect = std::abs(prediction.motion.phi) > m_params.glitch_min_turn ||
		prediction.stepSeconds > m_params.glitch_min_gap;
	if (suspect && (!match || disagrees) && m_params.wide_search_angle > 0)
	{
		if (auto wide = m_matcher.matchWide(cloud, scan, guess, m_params.wide_search_angle))
		{
			match = wide;
			reg.wideSearch = true;
		}
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
	// Rotate the covariance from the newest keyframe's axes to the map axes.
	const double c = std::cos(newestInMap.phi), s = std::sin(newestInMap.phi);
	Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
	R.topLeftCorner<2, 2>() << c, -s, s, c;
	reg.cov = R * match->cov * R.transpose();
	return reg;
}

size_t CLocalRegistration::linkAndOptimize(
	CPoseGraph& graph, const TKeyframes& keyframes, const TLink& odometryLink)
{
	const size_t newNode = graph.numNodes() - 1;
	graph.addLink(odometryLink);
	const std::vector<size_t> window = windowNodes(graph);
	// Pairwise matches of the new scan against up to max_pairwise_links window scans, the
	// previous keyframe first, then spread evenly back over the window (Lu & Milios' links).
	const size_t older = window.size() - 1;  // window nodes other than the new one
	const size_t links = std::min(m_params.max_pairwise_links, older);
	size_t added = 0;
	// Scan to map: the keyframe's registration against the window patch, in the frame of
	// the patch's reference node (the previous keyframe). Without it (the patch match failed)
	// the pairwise links keep their full weight: they are all the scans say then.
	double pairwiseWeight = 1.0;
	if (m_params.patch_link && m_lastPatchMatch && m_lastPatchMatch->node == newNode - 1)
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
		const size_t node = newNode - 1 - (l * older) / links;
		const TPose2D guess = between(graph.pose(node), graph.pose(newNode));
		const auto m = m_matcher.match(keyframeCloud(node, keyframes), keyframes[newNode].scan, guess);
		if (!m || m->inlierFraction < m_params.min_link_inliers) continue;
		graph.addLink(
			{node, newNode, m->scanInRef,
			 linkInformation(m->cov, m_params.link_noise, double(links) / pairwiseWeight),
			 LinkType::ScanMatch});
		++added;
	}
	// Node 0 anchors the map frame (gauge): it never moves.
	std::vector<size_t> freeNodes;
	for (const size_t node : window)
		if (node != 0) freeNodes.push_back(node);
	m_optimizer.optimizeSubset(graph, freeNodes);
	m_cloudNewest.reset();  // window poses moved
	return added;
}

}  // namespace lrgc
