/* CLocalRegistration, a new keyframe's links and the window solve (paper 2.2, Lu & Milios
 * over the last K keyframes): its patch link, its pairwise matches against the window's
 * scans, and the solve of the window's free poses. Registering each scan:
 * LocalRegistration.cpp; the window's patch prepared on the helper thread:
 * LocalRegistration_window.cpp. */
#include <lrgc/local_registration/LocalRegistration.h>

#include <lrgc/common/OrderStatistic.h>
#include <lrgc/common/se2.h>

#include <Eigen/Dense>
#include <algorithm>

namespace lrgc
{
// The reasoning and the measurements: LocalRegistration.h.
Eigen::Matrix3d lonePatchLinkCov(const Eigen::Matrix3d& cov, const TScan2D& scan, double r)
{
	return widenedPosition(cov, sparseReturnsRatio(scan, r));
}

double sparseReturnsRatio(const TScan2D& scan, double r)
{
	if (scan.points.size() < 2 || r <= 0) return 1;
	std::vector<double> d(scan.points.size() - 1);
	for (size_t i = 1; i < scan.points.size(); ++i)
		d[i - 1] = (scan.points[i] - scan.points[i - 1]).norm();
	return std::max(1.0, upperMedian(d) / r);
}

Eigen::Matrix3d widenedPosition(const Eigen::Matrix3d& cov, double ratio)
{
	if (ratio <= 1) return cov;
	const Eigen::DiagonalMatrix<double, 3> D(ratio, ratio, 1.0);
	return D * cov * D;
}

std::vector<std::optional<TScanMatch>> CLocalRegistration::matchAll(
	const std::vector<TCloudPtr>& refs, const TScan2D& scan,
	const std::vector<TPose2D>& guesses)
{
	std::vector<std::optional<TScanMatch>> results(refs.size());
	parallelFor(refs.size(),
				[&](size_t l) { results[l] = m_matcher.match(*refs[l], scan, guesses[l]); });
	return results;
}

// Two keyframes no scan match placed: their scans' match may not overrule the odometry between
// them (an unmatched scan never bends the map, issue 28 item 3). The guess is their relative
// pose as the odometry placed them.
bool CLocalRegistration::overrulesOdometry(size_t newNode, size_t node, const TPose2D& guess,
										   const TScanMatch& match,
										   const TLink& odometryLink) const
{
	return isUnplaced(newNode) && isUnplaced(node) &&
		   disagreementChi2(guess, match.scanInRef,
							odometryLink.information.inverse() + match.cov) >
			   m_params.glitch_gate_chi2;
}

// Where the pairwise matches put a keyframe whose patch match failed: each match implies a pose
// of the keyframe in the map (the window keyframe's pose composed with the match), and the
// matches vote (majorityBasin). On the sparse logs the matches of such keyframes were mostly
// right where the prior was off (3-20 deg from the guess), and a wrong one disagreed with the
// others (sparse ACES 133 -> 139: 41 deg off, against 138 -> 139 and 136 -> 139).
std::vector<std::optional<TPose2D>> CLocalRegistration::impliedPoses(
	const CPoseGraph& graph, const std::vector<size_t>& nodes,
	const std::vector<std::optional<TScanMatch>>& matches) const
{
	std::vector<std::optional<TPose2D>> implied(matches.size());
	for (size_t l = 0; l < matches.size(); ++l)
		if (matches[l] && matches[l]->inlierFraction >= m_params.min_link_inlier_fraction)
			implied[l] = compose(graph.pose(nodes[l]), matches[l]->scanInRef);
	return implied;
}

// The basin a strict majority of the implied poses agrees on (the previous anchor's first on
// equal support); none on a tie.
std::optional<TPose2D> CLocalRegistration::majorityBasin(
	const std::vector<std::optional<TPose2D>>& implied)
{
	auto support = [&](const TPose2D& p)
	{
		return std::count_if(implied.begin(), implied.end(),
							 [&](const auto& q)
							 { return q && !CScanMatcher::distinctHypotheses(p, *q); });
	};
	const auto voters = std::count_if(implied.begin(), implied.end(),
									  [](const auto& q) { return q.has_value(); });
	std::optional<TPose2D> best;
	std::ptrdiff_t bestSupport = 0;
	for (const auto& p : implied)
		if (const auto n = p ? support(*p) : 0; n > bestSupport) best = p, bestSupport = n;
	if (2 * bestSupport <= voters) return std::nullopt;
	return best;
}

// A keyframe whose patch match failed from its prior, where its pairwise matches agree on a
// basin: the patch match again, started there (a start the prior's error kept the plain match
// and its retry from: sparse MIT-CSAIL 25, odometry 21 deg short of a turn, the plain match
// 15 deg the other way at rms 0.104 m > 0.1; from the pairwise basin the patch match lands
// 0.1 deg and 2 cm from the dense run). It must pass every check of a plain match and stay in
// that basin. The patch holds the scans the scan was registered against: the window without
// the new keyframe, in the previous anchor's frame, at the poses it has now. It is built on
// the matcher's own cells (ref_resolution_m), not the window patch's noise-sized ones
// (patchParams()): the same on the real logs, 2 cm against 4 cm on the synthetic ones.
bool CLocalRegistration::reseedPatchMatch(CPoseGraph& graph, const TKeyframes& keyframes,
										  size_t from, size_t newNode, const TPose2D& basin)
{
	std::vector<TScan2D> scans;
	std::vector<TPose2D> inFrom;
	for (const size_t node : m_window)
	{
		if (node == newNode) continue;
		scans.push_back(keyframes[node].scan);
		inFrom.push_back(between(graph.pose(from), graph.pose(node)));
	}
	const CReferenceCloud patch = CReferenceCloud::fromScans(scans, inFrom, m_matcherParams);
	const TPose2D start = between(graph.pose(from), basin);
	const auto match = plainMatch(patch, keyframes[newNode].scan, start);  // cov at once
	if (!match || CScanMatcher::distinctHypotheses(start, match->scanInRef)) return false;
	// The keyframe stands where the patch puts it, placed by a scan match.
	m_lastPatchMatch = TPatchMatch{from, match->scanInRef, match->cov, nullptr};
	graph.setPose(newNode, compose(graph.pose(from), match->scanInRef));
	m_unplaced.erase(std::find(m_unplaced.begin(), m_unplaced.end(), newNode));
	++m_keyframesReseeded;
	return true;
}

// A disputed keyframe leaves the window: one of the two odometry readings is off, and a
// one-reading glitch puts the older keyframe off (its step and the next read wrong, their sum
// right); left in the patch, its scan where it is not would refuse every later match (free
// space). If the newer reading was the glitch, the next keyframe disputes it in turn.
void CLocalRegistration::leaveWindow(size_t node)
{
	m_window.erase(std::find(m_window.begin(), m_window.end(), node));
	m_unplaced.erase(std::find(m_unplaced.begin(), m_unplaced.end(), node));
}

size_t CLocalRegistration::linkAndOptimize(CPoseGraph& graph, const TKeyframes& keyframes,
										   const TLink& odometryLink)
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
	bool patchLink =
		m_params.patch_link && m_lastPatchMatch && m_lastPatchMatch->node == odometryLink.from;
	takeNewestCloud();  // the previous anchor's, prepared with the last patch
	std::vector<size_t> nodes;
	std::vector<TCloudPtr> refs;
	std::vector<TPose2D> guesses;
	for (size_t l = 0; l < links; ++l)
	{
		const size_t node = window[older - 1 - (l * older) / links];
		nodes.push_back(node);
		refs.push_back(keyframeCloud(node, keyframes));
		guesses.push_back(between(graph.pose(node), graph.pose(newNode)));
	}
	const auto matches = matchAll(refs, keyframes[newNode].scan, guesses);
	// The patch match failed from the prior: run it again from where the pairwise matches
	// agree the keyframe is, if they do (reseedPatchMatch); only after an odometry prior
	// (m_patchLinkable), the error the re-run is for.
	if (!patchLink && m_params.patch_link && m_patchLinkable && isUnplaced(newNode))
		if (const auto basin = majorityBasin(impliedPoses(graph, nodes, matches)))
			patchLink = reseedPatchMatch(graph, keyframes, odometryLink.from, newNode, *basin);
	const double pairwiseWeight = patchLink ? m_params.pairwise_link_weight : 1.0;
	auto confirms = [&](const std::optional<TScanMatch>& m)
	{ return m && m->inlierFraction >= m_params.min_link_inlier_fraction; };
	if (patchLink)  // added before the pairwise links, as their ids have always been
	{
		const Eigen::Matrix3d& matched = m_lastPatchMatch->cov.get();  // the helper's, likely
		Eigen::Matrix3d cov = matched;
		if (std::none_of(matches.begin(), matches.end(), confirms))
			cov =
				lonePatchLinkCov(cov, keyframes[newNode].scan, m_matcherParams.normal_radius_m);
		m_patchLinksWidened += cov != matched;
		graph.addLink({m_lastPatchMatch->node, newNode, m_lastPatchMatch->scanInNode,
					   linkInformation(cov, m_params.patch_link_noise), LinkType::ScanMatch});
		++added;
	}
	m_lastPatchMatch.reset();
	std::vector<size_t> disputed;
	for (size_t l = 0; l < links; ++l)
	{
		const auto& m = matches[l];
		if (!confirms(m)) continue;
		if (overrulesOdometry(newNode, nodes[l], guesses[l], *m, odometryLink))
		{
			disputed.push_back(nodes[l]);
			continue;
		}
		graph.addLink(
			{nodes[l], newNode, m->scanInRef,
			 linkInformation(m->cov, m_params.link_noise, double(links) / pairwiseWeight),
			 LinkType::ScanMatch});
		++added;
	}
	for (const size_t node : disputed) leaveWindow(node);
	// Node 0 anchors the map frame (gauge): it never moves; nor do keyframes the robot came
	// back to (the map's), nor any node older than the last of those.
	std::vector<size_t> freeNodes;
	for (const size_t node : window)
		if (node != 0 && node >= m_firstFree) freeNodes.push_back(node);
	if (!freeNodes.empty()) m_optimizer.optimizeSubset(graph, freeNodes);
	m_cloudNewest.reset();  // window poses moved
	prepareNextWindow(graph, keyframes);
	return added;
}

}  // namespace lrgc
