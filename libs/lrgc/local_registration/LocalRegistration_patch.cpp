/* CLocalRegistration, the window and its patch: a keyframe entering the window
 * (enterKeyframe), the patch the scans are matched against (windowCloud, patchOf, patchParams),
 * a match's evidence from the window (withEvidence), and the window's size by the prior
 * (resizeWindowFor). Registering each scan: LocalRegistration.cpp; the helper thread's share of
 * the patch: LocalRegistration_window.cpp. */
#include <lrgc/local_registration/LocalRegistration.h>

#include <lrgc/common/se2.h>

#include <algorithm>
#include <cmath>

namespace lrgc
{
using mrpt::math::TPose2D;
void CLocalRegistration::enterKeyframe(size_t node, bool reused, const CPoseGraph& graph,
									   bool placedByMatch)
{
	if (const auto it = std::find(m_window.begin(), m_window.end(), node); it != m_window.end())
		m_window.erase(it);
	m_window.push_back(node);
	while (m_window.size() > windowSize()) m_window.pop_front();
	if (!placedByMatch) m_unplaced.push_back(node);
	m_unplaced.erase(
		std::remove_if(m_unplaced.begin(), m_unplaced.end(),
					   [&](size_t n) { return !inWindow(n) || (n == node && placedByMatch); }),
		m_unplaced.end());
	if (reused) m_firstFree = graph.numNodes();
	m_cloudNewest.reset();
}

const CReferenceCloud& CLocalRegistration::windowCloud(const CPoseGraph& graph,
													   const TKeyframes& keyframes)
{
	const size_t newest = m_window.back();
	if (m_cloudNewest == newest) return *m_cloud;
	if (!takePreparedWindow(graph))
	{
		std::vector<TScan2D> scans;
		std::vector<TPose2D> posesInMap;
		for (const size_t node : windowNodes())
		{
			scans.push_back(keyframes[node].scan);
			posesInMap.push_back(graph.pose(node));
		}
		m_cloud =
			std::make_shared<const CReferenceCloud>(patchOf(scans, posesInMap, patchParams()));
		m_cloudNewest = newest;
	}
	m_patchNoiseStd = m_patchNoise.add(std::sqrt(m_cloud->noiseVariance()));
	return *m_cloud;
}

TScanMatcherParams CLocalRegistration::patchParams() const
{
	TScanMatcherParams p = m_matcherParams;
	p.ref_resolution_m = CReferenceCloud::cellForNoise(p.ref_resolution_m, m_patchNoiseStd,
													   0.5 * p.normal_radius_m);
	return p;
}

std::optional<TScanMatch> CLocalRegistration::withEvidence(const CPoseGraph& graph,
														   const TKeyframes& keyframes,
														   const TScan2D& scan,
														   std::optional<TScanMatch> wide)
{
	if (!wide || std::none_of(m_unplaced.begin(), m_unplaced.end(),
							  [&](size_t n) { return inWindow(n); }))
		return wide;
	// The window's patch without the keyframes no scan match placed, in the same frame (the
	// newest keyframe's, *m_cloudNewest).
	const TPose2D newestInMap = graph.pose(*m_cloudNewest);
	std::vector<TScan2D> scans;
	std::vector<TPose2D> inNewest;
	for (const size_t node : m_window)
	{
		if (std::find(m_unplaced.begin(), m_unplaced.end(), node) != m_unplaced.end()) continue;
		scans.push_back(keyframes[node].scan);
		inNewest.push_back(between(newestInMap, graph.pose(node)));
	}
	if (scans.empty()) return std::nullopt;
	const CReferenceCloud evidence = CReferenceCloud::fromScans(scans, inNewest, patchParams());
	const auto held = m_matcher.match(evidence, scan, wide->scanInRef);
	if (!held || CScanMatcher::distinctHypotheses(held->scanInRef, wide->scanInRef))
		return std::nullopt;
	return wide;
}

CReferenceCloud CLocalRegistration::patchOf(const std::vector<TScan2D>& scans,
											const std::vector<TPose2D>& posesInMap,
											const TScanMatcherParams& p,
											const TParallelFor& parallel)
{
	// The patch: every window scan with its pose in the newest keyframe's frame,
	// (newest <- node); the cloud keeps their range images for the free-space check.
	std::vector<TPose2D> scansInNewest;
	for (const TPose2D& pose : posesInMap)
		scansInNewest.push_back(between(posesInMap.back(), pose));
	// Its noise model's fit terms are not recorded (recordFitTerms): the next scans' matches
	// read them again, but the record cost 5 MB of peak RSS on range_030_bearing_015 (4 cm
	// cells, fits at 4 normal_radius_m) for 1-2 % of the instructions (doc/architecture.md).
	return CReferenceCloud::fromScans(scans, scansInNewest, p, parallel);
}

// K depends on the prior (window_size with odometry, laser_only_window_size without): a change
// of prior resizes the window, dropping its oldest keyframes if it shrinks. (An odometry jump
// is one step without the odometry, not a robot without it.)
void CLocalRegistration::resizeWindowFor(const TMotionPrediction& prediction)
{
	const bool withOdometry = prediction.fromOdometry || prediction.odometryJump;
	if (m_withOdometry == withOdometry) return;
	m_withOdometry = withOdometry;
	if (m_window.size() <= windowSize()) return;
	while (m_window.size() > windowSize()) m_window.pop_front();
	m_cloudNewest.reset();
}

}  // namespace lrgc
