#include <lrgc/loop_closing/LoopCloser.h>

#include <lrgc/scan_matching/ReferenceCloud.h>
#include <lrgc/loop_closing/UncertaintyPropagation.h>
#include <lrgc/common/params_io.h>
#include <lrgc/common/se2.h>

#include <mrpt/config/CConfigFileBase.h>

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>

namespace lrgc
{
using mrpt::math::TPose2D;

void TLoopCloserParams::loadFromConfigFile(
	const mrpt::config::CConfigFileBase& c, const std::string& s)
{
	rejectUnknownKeys(TLoopCloserParams(), c, s);
	old_map_exclusion = c.read_uint64_t(s, "old_map_exclusion", old_map_exclusion);
	patch_min_keyframes = c.read_uint64_t(s, "patch_min_keyframes", patch_min_keyframes);
	patch_keyframes_per_m = c.read_double(s, "patch_keyframes_per_m", patch_keyframes_per_m);
	gate_sigma = c.read_double(s, "gate_sigma", gate_sigma);
	overlap_radius = c.read_double(s, "overlap_radius", overlap_radius);
	window_sigmas = c.read_double(s, "window_sigmas", window_sigmas);
	max_window_xy = c.read_double(s, "max_window_xy", max_window_xy);
	max_window_theta = mrpt::DEG2RAD(
		c.read_double(s, "max_window_theta_deg", mrpt::RAD2DEG(max_window_theta)));
	consistent_chi2 = c.read_double(s, "consistent_chi2", consistent_chi2);
	check_every = c.read_uint64_t(s, "check_every", check_every);
	patch_max_range = c.read_double(s, "patch_max_range", patch_max_range);
	link_noise.load(c, s, "");
	requireParam(patch_max_range > 0, s, "patch_max_range", "must be > 0");
	requireParam(
		patch_min_keyframes >= 1 && patch_min_keyframes <= old_map_exclusion, s,
		"patch_min_keyframes", "must be in [1, old_map_exclusion]");
	requireParam(patch_keyframes_per_m >= 0, s, "patch_keyframes_per_m", "must be >= 0");
	requireParam(gate_sigma > 0, s, "gate_sigma", "must be > 0");
	requireParam(overlap_radius >= 0, s, "overlap_radius", "must be >= 0");
	requireParam(window_sigmas > 0, s, "window_sigmas", "must be > 0");
	requireParam(max_window_xy > 0, s, "max_window_xy", "must be > 0");
	requireParam(
		max_window_theta > 0 && max_window_theta <= M_PI, s, "max_window_theta_deg",
		"must be in (0, 180]");
	requireParam(consistent_chi2 > 0, s, "consistent_chi2", "must be > 0");
	requireParam(check_every >= 1, s, "check_every", "must be >= 1");
}

void TLoopCloserParams::saveToConfigFile(
	mrpt::config::CConfigFileBase& c, const std::string& s) const
{
	const int np = mrpt::config::MRPT_SAVE_NAME_PADDING(), vp = mrpt::config::MRPT_SAVE_VALUE_PADDING();
	c.write(s, "old_map_exclusion", uint64_t(old_map_exclusion), np, vp, "m: newest keyframes left out of the old map (m > K)");
	c.write(s, "patch_min_keyframes", uint64_t(patch_min_keyframes), np, vp, "Map patch size (keyframes) at zero uncertainty");
	c.write(s, "patch_keyframes_per_m", patch_keyframes_per_m, np, vp, "[1/m] Patch growth per metre of position std (capped at old_map_exclusion)");
	c.write(s, "gate_sigma", gate_sigma, np, vp, "Mahalanobis gate on old poses' position relative to the current one");
	c.write(s, "overlap_radius", overlap_radius, np, vp, "[m] Poses closer than this can see the same walls");
	c.write(s, "window_sigmas", window_sigmas, np, vp, "Correlation search half-window, in position/heading std devs");
	c.write(s, "max_window_xy", max_window_xy, np, vp, "[m] Cap of the translational search half-window");
	c.write(s, "max_window_theta_deg", mrpt::RAD2DEG(max_window_theta), np, vp, "[deg] Cap of the rotational search half-window");
	c.write(s, "consistent_chi2", consistent_chi2, np, vp, "[chi2, 3 dof] A loop link this consistent is added without a full solve");
	c.write(s, "check_every", uint64_t(check_every), np, vp, "Look for a loop every this many keyframes");
	c.write(s, "patch_max_range", patch_max_range, np, vp, "[m] Patch points farther than this from the newest keyframe are left out of the correlation");
	link_noise.save(c, s, "", "every loop link (scans minutes apart: moved objects)");
}

struct CLoopCloser::TCandidates
{
	std::vector<size_t> nodes;  //!< gated old nodes
	double sigmaXY = 0, sigmaTheta = 0;  //!< largest position / heading std among them
};

CLoopCloser::CLoopCloser(
	const TLoopCloserParams& p, const TPatchCorrelatorParams& correlator,
	const TScanMatcherParams& matcher, const TPoseGraphOptimizerParams& optimizer,
	const TLinkNoise& linkNoise)
	: m_params(p),
	  m_matcherParams(matcher),
	  m_linkNoise(linkNoise),
	  m_correlator(correlator),
	  m_matcher(matcher),
	  m_optimizer(optimizer)
{
}

// Step 1: old poses that could overlap the newest one, by Mahalanobis distance of their
// position relative to it, the offset first shortened by the overlap radius:
//   t' = t (1 - r / |t|)_+ ,  d^2 = t'^T C_xy^-1 t'  <=  gate_sigma^2.
auto CLoopCloser::gate(const CPoseGraph& graph, size_t newest) const -> std::optional<TCandidates>
{
	if (newest < m_params.old_map_exclusion) return std::nullopt;
	const size_t lastOld = newest - m_params.old_map_exclusion;
	TUncertaintyLimits limits;
	limits.maxPositionStd = m_params.max_window_xy / m_params.window_sigmas * 2;
	TCandidates c;
	for (const auto& r : propagateUncertainty(graph, newest, limits))
	{
		if (r.node > lastOld) continue;
		const Eigen::Vector2d t(r.nodeInSource.x, r.nodeInSource.y);
		const double norm = t.norm();
		const Eigen::Vector2d ts =
			norm > m_params.overlap_radius ? Eigen::Vector2d(t * (1 - m_params.overlap_radius / norm))
										   : Eigen::Vector2d::Zero();
		const Eigen::Matrix2d Cxy = r.cov.topLeftCorner<2, 2>() + 1e-6 * Eigen::Matrix2d::Identity();
		if (ts.dot(Cxy.ldlt().solve(ts)) > m_params.gate_sigma * m_params.gate_sigma) continue;
		c.nodes.push_back(r.node);
		c.sigmaXY = std::max(c.sigmaXY, std::sqrt(std::max(Cxy(0, 0), Cxy(1, 1))));
		c.sigmaTheta = std::max(c.sigmaTheta, std::sqrt(r.cov(2, 2)));
	}
	if (c.nodes.empty()) return std::nullopt;
	return c;
}

std::optional<TLoopClosure> CLoopCloser::process(CPoseGraph& graph, const TKeyframes& keyframes)
{
	m_lastRejection.clear();
	if (++m_keyframesSinceCheck < m_params.check_every) return std::nullopt;
	m_keyframesSinceCheck = 0;
	const size_t newest = graph.numNodes() - 1;
	const auto candidates = gate(graph, newest);
	if (!candidates) return std::nullopt;
	const auto t0 = std::chrono::steady_clock::now();
	const TPose2D newestInMap = graph.pose(newest);

	// Search window and patch size from the uncertainty (paper 2.4).
	const double winXY = std::clamp(
		m_params.window_sigmas * candidates->sigmaXY, 2 * m_correlator.params().resolution,
		m_params.max_window_xy);
	const double winTheta = std::clamp(
		m_params.window_sigmas * candidates->sigmaTheta, mrpt::DEG2RAD(2.0),
		m_params.max_window_theta);
	const size_t patchSize = std::min<size_t>(
		m_params.old_map_exclusion,
		m_params.patch_min_keyframes +
			static_cast<size_t>(m_params.patch_keyframes_per_m * candidates->sigmaXY));
	const size_t patchFirst = newest + 1 - std::min(patchSize, newest + 1);

	// Step 2: the patch (in the newest keyframe's frame) against the old map (map frame).
	std::vector<Eigen::Vector2d> patch, oldMap;
	double patchRadius = 0;
	for (size_t k = patchFirst; k <= newest; ++k)
	{
		const CPointTransform kInNewest(between(newestInMap, graph.pose(k)));
		for (const auto& p : keyframes[k].scan.points)
		{
			const Eigen::Vector2d q = kInNewest(p);
			const double range = q.norm();
			if (range > m_params.patch_max_range) continue;
			patch.push_back(q);
			patchRadius = std::max(patchRadius, range);
		}
	}
	const Eigen::Vector2d centre(newestInMap.x, newestInMap.y);
	const double reach = winXY + patchRadius + 3 * m_correlator.params().blurSigma;
	for (const size_t j : candidates->nodes)
	{
		const CPointTransform toMap(graph.pose(j));
		for (const auto& p : keyframes[j].scan.points)
			if (Eigen::Vector2d q = toMap(p); (q - centre).squaredNorm() <= reach * reach)
				oldMap.push_back(q);
	}
	if (oldMap.empty()) return std::nullopt;
	++m_stats.attempts;
	const CCorrelationGrid grid =
		m_correlator.makeGrid(oldMap, 3 * m_correlator.params().blurSigma);
	const auto corr = m_correlator.correlate(grid, patch, newestInMap, winXY, winTheta);
	const TCorrelationVerdict verdict = corr ? corr->checkFilters(m_correlator.params())
											 : TCorrelationVerdict{TCorrelationVerdict::Reason::LowScore, 0, m_correlator.params().minScore};
	if (!verdict.accepted())
	{
		++m_stats.rejectedByFilters;
		m_lastRejection = verdict.message();
		return std::nullopt;
	}

	// Step 3: refine with the scan matcher against the old scans near the nearest candidate.
	const TPose2D corrected = corr->patchInMap;
	size_t oldNode = candidates->nodes.front();
	double best = 1e18;
	for (const size_t j : candidates->nodes)
		if (const double d = translationNorm(between(graph.pose(j), corrected)); d < best)
			best = d, oldNode = j;
	const TPose2D oldInMap = graph.pose(oldNode);
	std::vector<TScan2D> refScans;
	std::vector<TPose2D> refInOld;
	for (const size_t j : candidates->nodes)
	{
		if (translationNorm(between(graph.pose(j), corrected)) > 2 * m_params.overlap_radius) continue;
		refScans.push_back(keyframes[j].scan);
		refInOld.push_back(between(oldInMap, graph.pose(j)));
	}
	// Only the old points the new scan can reach at the correlated pose (a few cm off):
	// correspondence gate plus the widest line fit, with margin to spare.
	const TPose2D guessInOld = between(oldInMap, corrected);
	std::vector<Eigen::Vector2d> scanInOld;
	const CPointTransform toOld(guessInOld);
	for (const auto& p : keyframes[newest].scan.points) scanInOld.push_back(toOld(p));
	const double cropMargin =
		m_matcherParams.maxCorrespondenceDist_m + 4 * m_matcherParams.normalRadius_m + 0.2;
	const auto match = m_matcher.match(
		CReferenceCloud::fromScansNear(refScans, refInOld, m_matcherParams, scanInOld, cropMargin),
		keyframes[newest].scan, guessInOld);
	if (!match)
	{
		++m_stats.rejectedByMatch;
		m_lastRejection = "correlation accepted but the scan match failed";
		return std::nullopt;
	}

	// Step 4: add the link; optimise if it moves the map.
	TLoopClosure lc;
	lc.oldNode = oldNode;
	lc.newNode = newest;
	lc.score = corr->score;
	lc.ambiguity = corr->ambiguity;
	const Eigen::Matrix3d info = linkInformation(match->cov, m_linkNoise);
	lc.linkId = graph.addLink({oldNode, newest, match->scanInRef, info, LinkType::LoopClosure});
	const Eigen::Vector3d e = linkResidual(oldInMap, newestInMap, match->scanInRef);
	if (e.dot(info * e) > m_params.consistent_chi2)
	{
		const auto report = m_optimizer.optimize(graph, 0);
		++m_stats.optimizations;
		if (std::binary_search(
				report.downweightedLinks.begin(), report.downweightedLinks.end(), lc.linkId))
		{
			++m_stats.rejectedByBackEnd;
			m_lastRejection = "loop link down-weighted by the robust back-end";
			graph.setLinkEnabled(lc.linkId, false);
			m_optimizer.optimize(graph, 0);
			return std::nullopt;
		}
		lc.optimized = true;
		lc.rematchLinks = rematch(graph, keyframes, *candidates, patchFirst, newest);
		if (lc.rematchLinks > 0) m_optimizer.optimize(graph, 0), ++m_stats.optimizations;
	}
	++m_stats.accepted;
	lc.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
	if (lc.optimized) m_stats.closureSeconds.push_back(lc.seconds);
	return lc;
}

// Paper 2.2: after the loop is closed, rerun with new scan matches between the newly linked
// poses. Each patch keyframe is matched against its nearest old candidate, now that the
// poses are topologically correct.
size_t CLoopCloser::rematch(
	CPoseGraph& graph, const TKeyframes& keyframes, const TCandidates& c, size_t patchFirst,
	size_t newest)
{
	size_t added = 0;
	for (size_t k = patchFirst; k < newest; k += 2)
	{
		size_t nearest = c.nodes.front();
		double best = 1e18;
		for (const size_t j : c.nodes)
			if (const double d = translationNorm(between(graph.pose(j), graph.pose(k))); d < best)
				best = d, nearest = j;
		if (best > m_params.overlap_radius) continue;
		const TPose2D guess = between(graph.pose(nearest), graph.pose(k));
		const auto m = m_matcher.match(
			CReferenceCloud::fromScan(keyframes[nearest].scan, m_matcherParams), keyframes[k].scan, guess);
		if (!m) continue;
		graph.addLink(
			{nearest, k, m->scanInRef, linkInformation(m->cov, m_linkNoise), LinkType::LoopClosure});
		++added;
	}
	return added;
}

}  // namespace lrgc
