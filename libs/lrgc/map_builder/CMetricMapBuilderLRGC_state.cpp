/* CMetricMapBuilderLRGC: the current estimate, and what the map builder hands out (CSimpleMap
 * of keyframes, trajectory; the occupancy grid: CMetricMapBuilderLRGC_grid.cpp). Initialisation
 * and continuing a saved map: CMetricMapBuilderLRGC_continue.cpp. */
#include <lrgc/map_builder/CMetricMapBuilderLRGC.h>
#include <lrgc/map_builder/IsolatedScans.h>
#include <lrgc/map_builder/KeyframeRematch.h>
#include <lrgc/map_builder/KeyframeReuse.h>
#include <lrgc/map_builder/ScanSmoothing.h>
#include <lrgc/local_registration/LocalRegistration.h>
#include <lrgc/local_registration/MotionPredictor.h>
#include <lrgc/loop_closing/LoopClosing.h>
#include <lrgc/loop_closing/RevisitLinker.h>
#include <lrgc/pose_graph/PoseGraphOptimizer.h>
#include <lrgc/common/se2.h>

#include <mrpt/img/CImage.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/poses/CPosePDF.h>

#include <algorithm>

namespace lrgc
{
using mrpt::math::TPose2D;

namespace
{
mrpt::poses::CPose3DPDFGaussian::Ptr gaussian3D(const TPose2D& p, const Eigen::Matrix3d& cov2D)
{
	auto pdf = mrpt::poses::CPose3DPDFGaussian::Create();
	pdf->mean = mrpt::poses::CPose3D(p.x, p.y, 0, p.phi, 0, 0);
	pdf->cov.setZero();
	// 2D (x, y, phi) into 3D (x, y, z, yaw, pitch, roll).
	const int idx[3] = {0, 1, 3};
	for (int r = 0; r < 3; ++r)
		for (int c = 0; c < 3; ++c) pdf->cov(idx[r], idx[c]) = cov2D(r, c);
	return pdf;
}
}  // namespace

mrpt::poses::CPose3DPDF::Ptr CMetricMapBuilderLRGC::getCurrentPoseEstimation() const
{
	const auto lock = lockMap();
	return gaussian3D(m_lastScanInMap, m_lastScanCov.get());
}

void CMetricMapBuilderLRGC::getCurrentlyBuiltMap(mrpt::maps::CSimpleMap& out_map) const
{
	const auto lock = lockMap();
	out_map.clear();
	for (size_t i = 0; i < m_keyframes.size(); ++i)
		out_map.insert(gaussian3D(m_graph.pose(i), Eigen::Matrix3d::Zero()),
					   m_keyframes[i].observations);
}

unsigned int CMetricMapBuilderLRGC::getCurrentlyBuiltMapSize()
{
	const auto lock = lockMap();
	return static_cast<unsigned int>(m_keyframes.size());
}

void CMetricMapBuilderLRGC::finish()
{
	const auto lock = lockMap();
	if (m_loops)
	{
		m_loops->searchDeferred(m_graph, m_keyframes);
		recordLoopUpdate(m_loops->drain(m_graph, anchor(), m_lastScanInMap));
	}
	if (!m_params.builder.final_optimization || m_graph.numNodes() < 2) return;
	if (m_loops && m_params.revisits.enabled)
	{
		CRevisitLinker linker(m_params.revisits, m_params.matcher, m_params.loop.link_noise);
		linker.setStopToken(m_stop);
		linker.setSplit(m_pieceFirst.value_or(0));  // no links across two frames
		const size_t added = linker.linkRevisits(m_graph, m_keyframes);
		m_stats.loopClosureLinks += added;
		m_stats.revisitLinks = added;
		MRPT_LOG_INFO_FMT("end of run: %zu revisit links re-matched", added);
	}
	if (m_loops)
	{
		rematchUnmatchedKeyframes();
		rematchFirstKeyframe();
	}
	CPoseGraphOptimizer optimizer(m_params.optimizer);
	optimizer.setStopToken(m_stop);
	const auto report = optimizer.optimize(m_graph, 0, {}, m_frozenNodes);
	// The links it down-weighted to (almost) nothing are rejected, as a closure's solve
	// rejects its link online: disabled, so that the saved graph (a continued map) and the
	// loop counts do not hold them. The poses stay: their weight in them was s^2 < 0.01.
	for (const size_t id : report.downweightedLinks)
		if (m_graph.isLinkEnabled(id))
			m_graph.setLinkEnabled(id, false), ++m_stats.finalRejectedLinks;
	MRPT_LOG_INFO_FMT("final optimisation: %zu nodes, %d iterations, chi2 %.3g -> %.3g%s",
					  m_graph.numNodes(), report.iterations, report.initialChi2,
					  report.finalChi2, report.stopped ? " (stopped)" : "");
	// A piece not joined to the map (startPiece) is optimised in its own frame, its first
	// node fixed as node 0 is the map's.
	if (m_pieceFirst && *m_pieceFirst + 1 < m_graph.numNodes())
		optimizer.optimize(m_graph, *m_pieceFirst);
	settleIsolatedScans();
	m_lastScanInMap = m_scans.empty() ? m_lastScanInMap
									  : compose(m_graph.pose(m_scans.back().node),
												m_scans.back().robotInNode);
	m_metricMapDirty = true;
}

void CMetricMapBuilderLRGC::setStopToken(const CStopToken& stop)
{
	const auto lock = lockMap();
	m_stop = stop;
	m_local->setStopToken(stop);
	m_reuse->setStopToken(stop);
	if (m_loops) m_loops->setStopToken(stop);
}

void CMetricMapBuilderLRGC::rematchUnmatchedKeyframes()
{
	// The keyframes a scan matched nothing for, mid-run: linked to the previous keyframe by
	// odometry (not a session's or a piece's first), free to move (not frozen, not node 0).
	std::vector<size_t> candidates;
	for (const auto& s : m_scans)
	{
		if (!s.keyframe || s.matched || s.node == 0 || s.node < m_frozenNodes) continue;
		const auto& ids = m_graph.linksOf(s.node);
		if (std::any_of(ids.begin(), ids.end(),
						[&](size_t id)
						{
							const TLink& l = m_graph.link(id);
							return l.to == s.node && l.type == LinkType::Odometry &&
								   m_graph.isLinkEnabled(id);
						}))
			candidates.push_back(s.node);
	}
	if (candidates.empty()) return;
	const CKeyframeRematcher rematcher = keyframeRematcher();
	const auto moved =
		rematcher.rematch(m_graph, m_keyframes, candidates, m_pieceFirst.value_or(0));
	// The other scans hanging from a moved keyframe were registered against the window's
	// patch, not against the keyframe's pose: they keep their place in the map.
	for (const auto& [node, before] : moved)
		for (auto& s : m_scans)
			if (s.node == node && !s.keyframe)
				s.robotInNode = between(m_graph.pose(node), compose(before, s.robotInNode));
	m_stats.keyframesRematched = moved.size();
	m_stats.loopClosureLinks += moved.size();  // stats.json: loop_links' rematch_or_reuse
	m_stats.keyframesLeftUnmatched = candidates.size() - moved.size();
	MRPT_LOG_INFO_FMT("end of run: %zu of %zu unmatched keyframes re-matched", moved.size(),
					  candidates.size());
}

CKeyframeRematcher CMetricMapBuilderLRGC::keyframeRematcher() const
{
	CKeyframeRematcher rematcher(m_params.matcher, m_params.local.wide_search_angle,
								 m_params.local.glitch_gate_chi2,
								 m_predictor->constantVelocityCov(), m_params.loop.link_noise);
	rematcher.setStopToken(m_stop);
	return rematcher;
}

void CMetricMapBuilderLRGC::rematchFirstKeyframe()
{
	// Node 0 is the map's anchor: the first keyframe of a new session (not of a saved map
	// continued, whose nodes are frozen). Online only the keyframes right after it were
	// matched against it, each against it alone, so one wrong first match turns the whole map
	// about the start (harsh museum, seed 1: the first step matched 8.5 deg off, agreeing with
	// odometry 7.4 deg off, and the map 6.9 m off its start 45 m away); later passes through
	// the start place are linked to keyframes 1 and after, never to 0.
	if (m_frozenNodes > 0 || m_graph.numNodes() < 3) return;
	const CKeyframeRematcher rematcher = keyframeRematcher();
	const TPose2D start = m_graph.pose(0);
	const auto moved = rematcher.rematch(m_graph, m_keyframes, {0}, m_pieceFirst.value_or(0));
	if (moved.empty()) return;
	// The match moved node 0 against the map; the map moves instead, rigidly (every node of
	// node 0's frame by T = start (+) moved^-1), so node 0 is back at its start pose. The
	// scans hanging from node 0 were matched against it alone: they stay with it.
	const TPose2D T = compose(start, inverse(m_graph.pose(0)));
	const size_t end = m_pieceFirst.value_or(m_graph.numNodes());
	for (size_t j = 0; j < end; ++j) m_graph.setPose(j, compose(T, m_graph.pose(j)));
	++m_stats.keyframesRematched;
	++m_stats.loopClosureLinks;  // stats.json: loop_links' rematch_or_reuse
	MRPT_LOG_INFO("end of run: the first keyframe re-matched, the map turned about it");
}

void CMetricMapBuilderLRGC::settleIsolatedScans()
{
	std::vector<TScanStep> steps;
	steps.reserve(m_scans.size());
	for (const auto& s : m_scans)
		steps.push_back({compose(m_graph.pose(s.node), s.robotInNode), s.step, s.stepCov,
						 s.registrationCov.get(), s.stepFromOdometry, s.keyframe});
	const auto settled = lrgc::settleIsolatedScans(steps);
	for (const auto& [i, pose] : settled) steps[i].pose = pose;
	m_stats.scansSettled = settled.size();
	// Then every scan between its keyframes (ScanSmoothing.h); keyframes' scans keep theirs.
	for (const auto& [i, pose] : smoothScans(steps, odometryNoiseScale(steps)))
		steps[i].pose = pose;
	for (size_t i = 0; i < m_scans.size(); ++i)
		m_scans[i].robotInNode = between(m_graph.pose(m_scans[i].node), steps[i].pose);
}

TTrajectory CMetricMapBuilderLRGC::trajectory() const
{
	const auto lock = lockMap();
	TTrajectory t;
	t.reserve(m_scans.size());
	for (const auto& s : m_scans)
		t.push_back({s.timestamp, compose(m_graph.pose(s.node), s.robotInNode)});
	return t;
}

TMapBuilderStats CMetricMapBuilderLRGC::statsCopy() const
{
	const auto lock = lockMap();
	return m_stats;
}

mrpt::Clock::time_point CMetricMapBuilderLRGC::lastScanTimestamp() const
{
	const auto lock = lockMap();
	return m_scans.empty() ? mrpt::Clock::time_point{} : m_scans.back().timestamp;
}

}  // namespace lrgc
