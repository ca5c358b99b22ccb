/* CMetricMapBuilderLRGC, step 3 of a scan's story (CMetricMapBuilderLRGC.cpp): where the scan
 * is placed. Near the anchor keyframe it hangs from it; on ground the map already has it moves
 * the anchor to the keyframe there (CKeyframeReuse, linked by the scan); else it becomes a new
 * keyframe, linked to the window by odometry, patch and pairwise matches and the window
 * re-estimated (Lu & Milios over the last K, CLocalRegistration). */
#include <lrgc/map_builder/CMetricMapBuilderLRGC.h>

#include <lrgc/common/se2.h>
#include <lrgc/local_registration/LocalRegistration.h>
#include <lrgc/local_registration/MotionPredictor.h>
#include <lrgc/map_builder/KeyframeReuse.h>

#include <Eigen/Dense>

namespace lrgc
{
using mrpt::math::TPose2D;

// Step 3: near its keyframe the scan hangs from it; farther, on ground the map already has, it
// anchors at the keyframe there (CKeyframeReuse); else it becomes a new keyframe.
void CMetricMapBuilderLRGC::placeScan(const mrpt::obs::CObservation2DRangeScan::Ptr& laser,
									  const mrpt::obs::CSensoryFrame::Ptr& observations,
									  TScan2D&& scan, const TRegistration& reg,
									  size_t scanIndex)
{
	const bool atStart =
		m_graph.numNodes() == 0 || m_sessionStartCov.has_value() || m_pieceStartPending;
	if (!atStart && !isNewKeyframe(reg.scanInMap))
		recordScan(laser->timestamp, anchor(), between(m_graph.pose(anchor()), reg.scanInMap));
	else if (const auto reused =
				 atStart || !reg.matched || reg.odometryRejected || reg.wideSearch
					 ? std::nullopt
					 : m_reuse->reusableKeyframe(m_graph, m_keyframes, scan, reg.scanInMap,
												 reg.cov, anchor(), m_local->window()))
		enterReusedKeyframe(*reused, reg, laser);
	else
		enterNewKeyframe(laser, observations, std::move(scan), reg, scanIndex);
}

// The robot's anchor moves to an existing keyframe, linked to the previous anchor by this
// scan (linkReused); a keyframe of an older session shows this scan from now on
// (showNewerScan); the loop results due are applied (no search: the keyframe is not new).
void CMetricMapBuilderLRGC::enterReusedKeyframe(
	const TReusedKeyframe& reused, const TRegistration& reg,
	const mrpt::obs::CObservation2DRangeScan::Ptr& laser)
{
	++m_stats.keyframesReused;
	linkReused(reused, reg);
	m_local->enterKeyframe(reused.node, true, m_graph);
	const TPose2D inNode = between(m_graph.pose(reused.node), reg.scanInMap);
	m_motionSinceKeyframe = inNode;  // the odometry link of a later keyframe starts here
	m_anchorOffset = inNode;
	if (m_keyframes[reused.node].session < m_session) showNewerScan(reused.node, laser, inNode);
	recordScan(laser->timestamp, reused.node, inNode);
	closeLoops(false);
}

// A new keyframe: a node at the registered pose, linked to the window (odometry, patch and
// pairwise matches) and the window re-estimated (Lu & Milios over the last K); a session's
// first keyframe is linked to the old map instead. Then steps 4-5, loops.
void CMetricMapBuilderLRGC::enterNewKeyframe(
	const mrpt::obs::CObservation2DRangeScan::Ptr& laser,
	const mrpt::obs::CSensoryFrame::Ptr& observations, TScan2D&& scan, const TRegistration& reg,
	size_t scanIndex)
{
	const std::optional<size_t> previous = m_local->anchor();
	// A keyframe linked to the window that no scan match placed (its prior kept): no evidence
	// for the wide search (LocalRegistration.h).
	const bool placedByMatch =
		reg.matched || !previous || m_pieceStartPending || m_sessionStartCov;
	const size_t node =
		addKeyframe(laser, observations, std::move(scan), reg.scanInMap, scanIndex);
	m_local->enterKeyframe(node, false, m_graph, placedByMatch);
	if (m_pieceStartPending)
		m_pieceStartPending = false;  // a piece's first keyframe: linked to nothing
	else if (m_sessionStartCov)
		linkSessionStart(node);  // to the old map, by a scan match
	else if (previous)
	{
		const size_t reseeded = m_local->keyframesReseeded();
		m_stats.scanMatchLinks +=
			m_local->linkAndOptimize(m_graph, m_keyframes, odometryLink(*previous, node));
		m_stats.patchLinksWidened = m_local->patchLinksWidened();
		// Its patch match found again from its pairwise matches: placed by a scan match.
		m_scanMatched = m_scanMatched || m_local->keyframesReseeded() > reseeded;
		m_stats.keyframesReseeded = m_local->keyframesReseeded();
		++m_stats.odometryLinks;
		closeLoops(true);
	}
	m_pathSinceKeyframe = m_turnSinceKeyframe = 0;
	m_lastScanInMap = m_graph.pose(node);
	m_motionSinceKeyframe = TPose2D(0, 0, 0);
	m_anchorOffset = TPose2D(0, 0, 0);
	m_odometryTrustedSinceKeyframe = true;
	recordScan(laser->timestamp, node, TPose2D(0, 0, 0), true);
}

void CMetricMapBuilderLRGC::recordScan(mrpt::Clock::time_point stamp, size_t node,
									   const TPose2D& robotInNode, bool keyframe)
{
	m_scans.push_back({stamp, node, robotInNode, m_scanStep, m_scanStepCov,
					   m_lastScanSmoothingCov, m_scanStepFromOdometry, keyframe,
					   m_scanMatched});
	// The records' deferred covariances (a plain match's, TRegistration::cov) settled
	// kSettleLag scans behind, long computed by then: a record keeps a matrix, not the
	// match's pairs and patch. The values are the same whenever they are settled.
	constexpr size_t kSettleLag = 8;
	for (; m_scansSettled + kSettleLag < m_scans.size(); ++m_scansSettled)
		m_scans[m_scansSettled].registrationCov.settle();
}

// The scan that moves the robot's anchor from keyframe a to an existing keyframe c measures
// their relative pose, as the reduced pose graph keeps a revisit's evidence (Johannsson et
// al. 2013): (a <- scan) from its registration against the window patch (in a's frame), and
// (c <- scan) from its match against c's scan, so
//     Z_ac = (a <- scan) (+) (c <- scan)^-1,  C_ac ~ C_a + R(Z_ac.phi) C_c R^T
// (the lever arm left out: the scan is within the cover radius of both). A loop link (the
// scans were taken at different times; robust in the whole-graph solves), with the loop
// links' noise floor.
void CMetricMapBuilderLRGC::linkReused(const TReusedKeyframe& c, const TRegistration& reg)
{
	const size_t a = anchor();
	const TPose2D aInMap = m_graph.pose(a);
	const TPose2D scanInA = between(aInMap, reg.scanInMap);
	const TPose2D z = compose(scanInA, inverse(c.scanInNode));
	const Eigen::Matrix3d covA = rotateCovariance(reg.cov.get(), -aInMap.phi);  // map -> a's
	const Eigen::Matrix3d covC = rotateCovariance(c.cov, z.phi);  // c's axes -> a's
	m_graph.addLink({a, c.node, z, linkInformation(covA + covC, m_params.loop.link_noise),
					 LinkType::LoopClosure});
	++m_stats.loopClosureLinks;
}

size_t CMetricMapBuilderLRGC::anchor() const
{
	return m_local->anchor().value_or(m_graph.numNodes() - 1);
}

bool CMetricMapBuilderLRGC::isNewKeyframe(const TPose2D& scanInMap) const
{
	const TPose2D d = between(compose(m_graph.pose(anchor()), m_anchorOffset), scanInMap);
	return translationNorm(d) >= m_params.builder.keyframe_distance_m ||
		   std::abs(d.phi) >= m_params.builder.keyframe_angle;
}

size_t CMetricMapBuilderLRGC::addKeyframe(const mrpt::obs::CObservation2DRangeScan::Ptr& laser,
										  const mrpt::obs::CSensoryFrame::Ptr& observations,
										  TScan2D&& scan, const TPose2D& scanInMap,
										  size_t scanIndex)
{
	const size_t node = m_graph.addNode(scanInMap);
	ASSERT_EQUAL_(node, m_keyframes.size());
	m_keyframes.push_back({std::move(scan), observations, laser, scanIndex, m_session});
	++m_stats.keyframes;
	return node;
}

// The odometry link (the anchor keyframe `from` -> the new keyframe `to`): the odometry
// motion composed over the scans in between with its proportional noise (from a reused
// keyframe: its registered offset, then the odometry); where odometry was absent or
// rejected as a glitch, the registered motion with the weak constant-velocity noise, so
// the graph stays connected without the link pulling the map.
TLink CMetricMapBuilderLRGC::odometryLink(size_t from, size_t to) const
{
	TLink link;
	link.from = from;
	link.to = to;
	link.type = LinkType::Odometry;
	if (m_odometryTrustedSinceKeyframe)
	{
		link.toInFrom = m_motionSinceKeyframe;
		link.information = m_predictor->odometryCov(m_motionSinceKeyframe).inverse();
	}
	else
	{
		link.toInFrom = between(m_graph.pose(from), m_graph.pose(to));
		link.information = m_predictor->constantVelocityCov().inverse();
	}
	return link;
}

}  // namespace lrgc
