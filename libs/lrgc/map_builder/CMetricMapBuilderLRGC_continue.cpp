/* CMetricMapBuilderLRGC: initialisation, and continuing a saved map.
 *
 * A map given to initialize() is continued, not just drawn: its keyframes become graph nodes.
 *  - A map saved by lrgc (map.simplemap.gz + graph.lrgc) comes back exactly: the same poses
 *    and the same links (odometry, scan match, loop closure, the disabled ones too), so the
 *    old loops stay closed and the robust back-end judges new loop links against them.
 *  - Any other CSimpleMap (icp-slam's) has poses but no links: consecutive keyframes are
 *    linked by scan matching from their stored relative pose (by that pose, tightly, where
 *    the match fails or contradicts it), and the places the map revisits by CRevisitLinker's
 *    loop links, so its loops are loops of the graph too.
 * A log that starts elsewhere in the old map starts a session (startSessionAt): its first scan
 * becomes a keyframe at the pose global localisation found, linked to the old map by a scan
 * match against the old keyframes around it, and the local registration window restarts
 * there. From then on the normal loop closer finds the loops between the session and the old
 * map.
 * A continued map's keyframes are session 0 and this run's session 1 (TKeyframe::session):
 * where the world changed since, the newer session's view wins, in the grid (CIncrementalGrid)
 * and in the keyframes it reuses (showNewerScan).
 */
#include <lrgc/map_builder/CMetricMapBuilderLRGC.h>
#include <lrgc/scan_matching/ScanGeometry.h>
#include <lrgc/map_builder/KeyframeReuse.h>

#include <lrgc/common/se2.h>
#include <lrgc/local_registration/LocalRegistration.h>
#include <lrgc/local_registration/MotionPredictor.h>
#include <lrgc/local_registration/SweepEstimator.h>
#include <lrgc/loop_closing/LoopClosing.h>
#include <lrgc/map_builder/TestAccess.h>
#include <lrgc/loop_closing/RevisitLinker.h>
#include <lrgc/scan_matching/ReferenceCloud.h>
#include <lrgc/scan_matching/ScanMatcher.h>

#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/poses/CPosePDF.h>

#include <Eigen/Dense>
#include <limits>

namespace lrgc
{
using mrpt::math::TPose2D;

namespace
{
/** Std of a link between consecutive keyframes of a simplemap where their scan match fails
 * [m, m, rad]: tight, since that map's poses are taken as they are. */
const Eigen::Vector3d kContinuationLinkStd(0.01, 0.01, mrpt::DEG2RAD(0.5));
/** A scan match of a consecutive pair or of a session's first scan is kept if it agrees with
 * its guess within chi2 <= 16.27 (3 dof, p = 0.001) under the guess's and the match's
 * covariance; otherwise the guess is the better evidence. */
constexpr double kAgreeChi2 = 16.27;

Eigen::Matrix3d informationOf(const Eigen::Vector3d& std)
{
	return std.cwiseProduct(std).cwiseInverse().asDiagonal();
}
}  // namespace

void CMetricMapBuilderLRGC::resetState()
{
	m_predictor = std::make_unique<CMotionPredictor>(m_params.motion);
	m_sweep = std::make_unique<CSweepEstimator>(m_params.sweep, m_params.matcher,
												m_params.builder.scan_sweep_time_s);
	m_local = std::make_unique<CLocalRegistration>(m_params.local, m_params.matcher,
												   m_params.optimizer);
	TScanMatcherParams localMatcher = m_params.matcher;  // as local registration's matches
	localMatcher.max_free_space_violation = m_params.local.max_free_space_violation;
	m_reuse = std::make_unique<CKeyframeReuse>(
		m_params.reuse, m_params.builder.keyframe_distance_m, m_params.builder.keyframe_angle,
		localMatcher, m_params.loop.link_noise);
	m_loops.reset();  // lets a search in hand finish first
	if (m_params.builder.loop_closing)
		m_loops = std::make_unique<CLoopClosing>(m_params.loop, m_params.correlator,
												 m_params.matcher, m_params.optimizer);
	m_local->setStopToken(m_stop);
	m_reuse->setStopToken(m_stop);
	if (m_loops) m_loops->setStopToken(m_stop);
	if (m_loops && m_loopSearchExtraDelay.count() > 0)
		TLoopClosingTestAccess::setExtraDelay(*m_loops, m_loopSearchExtraDelay);
	m_graph = CPoseGraph();
	m_keyframes.clear();
	m_scans.clear();
	m_scansSettled = 0;
	m_stats = {};
	m_lasers = CLaserSelector(m_params.builder);
	m_lastScanInMap = TPose2D(0, 0, 0);
	m_lastScanCov = CLazyCovariance(Eigen::Matrix3d::Zero());
	m_lastScanSmoothingCov = CLazyCovariance(Eigen::Matrix3d::Zero());
	m_nextScanPrior.reset();
	m_sessionStartCov.reset();
	m_pieceFirst.reset();
	m_pieceStartPending = false;
	m_frozenNodes = 0;
	m_motionSinceKeyframe = TPose2D(0, 0, 0);
	m_anchorOffset = TPose2D(0, 0, 0);
	m_odometryTrustedSinceKeyframe = true;
	m_scanMatched = true;
	m_session = 0;
	m_metricMapDirty = true;
}

// The keyframes of a CSimpleMap with their stored poses (returned in `poses`, not yet graph
// nodes). `all`: every entry must give a keyframe (an exact restore), else entries without a
// usable scan are skipped.
void CMetricMapBuilderLRGC::adoptKeyframes(const mrpt::maps::CSimpleMap& map,
										   const std::string& laserLabel, bool all)
{
	std::string label = laserLabel;
	for (size_t i = 0; i < map.size(); ++i)
	{
		const auto [posePDF, sf] = map.get(i);
		mrpt::obs::CObservation2DRangeScan::Ptr laser;
		if (posePDF && sf)
			for (const auto& o : *sf)
			{
				auto l = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(o);
				if (l && (label.empty() || l->sensorLabel == label))
				{
					laser = l;
					break;
				}
			}
		if (!laser)
		{
			if (all)
				THROW_EXCEPTION_FMT("initial map entry %zu has no pose or no 2D laser scan%s",
									i,
									label.empty() ? "" : (" labelled '" + label + "'").c_str());
			continue;
		}
		// Saved maps come through the same door as logs (ScanGeometry.h).
		const TScanGeometryCheck checked = checkScanGeometry(laser);
		if (!checked.scan)
		{
			if (all)
				THROW_EXCEPTION_FMT("initial map entry %zu: %s", i, checked.problem.c_str());
			continue;
		}
		laser = checked.scan;
		TScan2D scan = scanFromObservation(*laser);
		if (!all && scan.points.size() < m_params.builder.min_scan_points) continue;
		if (label.empty()) label = laser->sensorLabel;
		const auto mean = posePDF->getMeanVal();
		m_graph.addNode(TPose2D(mean.x(), mean.y(), mean.yaw()));
		m_keyframes.push_back(
			{std::move(scan), std::const_pointer_cast<mrpt::obs::CSensoryFrame>(sf), laser, i});
		++m_stats.keyframes;
	}
	if (!label.empty()) m_lasers.adopt(label);
}

// A simplemap's keyframes have poses only: chain them by scan matching, then link the places
// the map revisits (CRevisitLinker), as the end of a run does.
void CMetricMapBuilderLRGC::linkChainAndRevisits()
{
	const CScanMatcher matcher(m_params.matcher);
	const Eigen::Matrix3d guessCov = informationOf(kContinuationLinkStd).inverse();
	for (size_t i = 1; i < m_graph.numNodes(); ++i)
	{
		const TPose2D guess = between(m_graph.pose(i - 1), m_graph.pose(i));
		const auto m =
			matcher.match(CReferenceCloud::fromScan(m_keyframes[i - 1].scan, m_params.matcher),
						  m_keyframes[i].scan, guess);
		if (m && m->inlierFraction >= m_params.local.min_link_inlier_fraction &&
			disagreementChi2(guess, m->scanInRef, guessCov + m->cov) <= kAgreeChi2)
		{
			m_graph.addLink({i - 1, i, m->scanInRef,
							 linkInformation(m->cov, m_params.local.link_noise),
							 LinkType::ScanMatch});
			++m_stats.scanMatchLinks;
		}
		else
		{
			m_graph.addLink(
				{i - 1, i, guess, informationOf(kContinuationLinkStd), LinkType::Odometry});
			++m_stats.odometryLinks;
		}
	}
	if (m_params.revisits.enabled && m_graph.numNodes() > 1)
	{
		const CRevisitLinker linker(m_params.revisits, m_params.matcher,
									m_params.loop.link_noise);
		const size_t added = linker.linkRevisits(m_graph, m_keyframes);
		m_stats.loopClosureLinks += added;
		MRPT_LOG_INFO_FMT("initial map: %zu keyframes, %zu revisit links", m_graph.numNodes(),
						  added);
	}
}

void CMetricMapBuilderLRGC::initialize(const mrpt::maps::CSimpleMap& initialMap,
									   const mrpt::poses::CPosePDF* x0)
{
	const auto lock = lockMap();
	resetState();
	adoptKeyframes(initialMap, {}, false);
	m_session = m_keyframes.empty() ? 0 : 1;  // the map's keyframes are session 0
	linkChainAndRevisits();
	enterNewestKeyframes();
	if (m_graph.numNodes() > 0) m_lastScanInMap = m_graph.pose(m_graph.numNodes() - 1);
	if (x0)
	{
		const auto mean = x0->getMeanVal();
		m_nextScanPrior = TPose2D(mean.x(), mean.y(), mean.phi());
	}
	else if (m_graph.numNodes() > 0)
		m_nextScanPrior = m_lastScanInMap;
}

void CMetricMapBuilderLRGC::initialize(const mrpt::maps::CSimpleMap& keyframes,
									   const CPoseGraph& graph, const std::string& laserLabel,
									   const std::vector<size_t>& sessions)
{
	if (keyframes.size() != graph.numNodes())
		THROW_EXCEPTION_FMT(
			"the saved map has %zu keyframes but its graph %zu nodes: they are not of the same "
			"run",
			keyframes.size(), graph.numNodes());
	if (!sessions.empty() && sessions.size() != graph.numNodes())
		THROW_EXCEPTION_FMT("the saved map's graph has %zu nodes but %zu sessions",
							graph.numNodes(), sessions.size());
	const auto lock = lockMap();
	resetState();
	adoptKeyframes(keyframes, laserLabel, true);
	// The map's keyframes keep their sessions (0 where none is saved); this run is the next.
	m_session = m_keyframes.empty() ? 0 : 1;
	for (size_t i = 0; i < sessions.size(); ++i)
	{
		m_keyframes[i].session = sessions[i];
		m_session = std::max(m_session, sessions[i] + 1);
	}
	m_graph = graph;  // the poses and links exactly as saved
	enterNewestKeyframes();
	if (m_graph.numNodes() > 0)
	{
		m_lastScanInMap = m_graph.pose(m_graph.numNodes() - 1);
		m_nextScanPrior = m_lastScanInMap;
	}
}

// The map's newest keyframes form the local window, as if just mapped: the next scans
// continue from the end of the map.
void CMetricMapBuilderLRGC::enterNewestKeyframes()
{
	const size_t n = m_graph.numNodes(), k = m_params.local.window_size;
	for (size_t i = n > k ? n - k : 0; i < n; ++i) m_local->enterKeyframe(i, false, m_graph);
}

void CMetricMapBuilderLRGC::startSessionAt(const TPose2D& scanInMap, const Eigen::Matrix3d& cov)
{
	const auto lock = lockMap();
	ASSERTMSG_(m_graph.numNodes() > 0, "startSessionAt() needs a map to start in");
	ASSERTMSG_(cov.allFinite(), "startSessionAt(): the covariance is not finite");
	m_predictor = std::make_unique<CMotionPredictor>(m_params.motion);  // a new log
	m_sweep->startNewLog();  // same laser: the estimate stays, the recent scans go
	m_local->setWindowStart(m_graph.numNodes());
	m_nextScanPrior = scanInMap;
	m_lastScanInMap = scanInMap;  // so the first step's motion is not a jump from the old end
	m_sessionStartCov = cov;
	for (const TKeyframe& k : m_keyframes) m_session = std::max(m_session, k.session + 1);
	m_motionSinceKeyframe = TPose2D(0, 0, 0);
	m_anchorOffset = TPose2D(0, 0, 0);
	m_odometryTrustedSinceKeyframe = true;
}

// The first keyframe of a session: linked to the nearest old keyframe by a scan match against
// the old keyframes within overlap_radius_m (linkToMap), placed where the match puts it;
// without an agreeing match, by the start pose with the localisation's covariance.
void CMetricMapBuilderLRGC::linkSessionStart(size_t node)
{
	const Eigen::Matrix3d cov = *m_sessionStartCov;
	m_sessionStartCov.reset();
	const TPose2D start = m_graph.pose(node);
	const TMapLink j = linkToMap(node, start, cov, node);
	if (j.problem.empty())
		m_graph.setPose(node, j.nodeInMap);
	else
		warn(mrpt::format(
			"session start at (%.2f, %.2f, %.1f deg): %s; linked by the global localisation "
			"alone",
			start.x, start.y, mrpt::RAD2DEG(start.phi), j.problem.c_str()));
	m_graph.addLink(j.link);
	m_reuse->noteLoopLink(node);
	++m_stats.loopClosureLinks;
	m_local->invalidate();
	MRPT_LOG_INFO_FMT("session starts at keyframe %zu, linked to old keyframe %zu", node,
					  j.link.from);
}

// The map's keyframes within overlap_radius_m of the guess, in the nearest one's frame, are
// the reference of a scan match of `node`'s scan from the guess.
CMetricMapBuilderLRGC::TMapLink CMetricMapBuilderLRGC::linkToMap(size_t node,
																 const TPose2D& guessInMap,
																 const Eigen::Matrix3d& cov,
																 size_t mapEnd) const
{
	size_t nearest = 0;
	double best = std::numeric_limits<double>::infinity();
	for (size_t j = 0; j < mapEnd; ++j)
		if (const double d = translationNorm(between(m_graph.pose(j), guessInMap)); d < best)
			best = d, nearest = j;
	const TPose2D nearestInMap = m_graph.pose(nearest);
	std::vector<TScan2D> scans;
	std::vector<TPose2D> scansInNearest;
	for (size_t j = 0; j < mapEnd; ++j)
		if (translationNorm(between(m_graph.pose(j), guessInMap)) <=
			m_params.loop.overlap_radius_m)
		{
			scans.push_back(m_keyframes[j].scan);
			scansInNearest.push_back(between(nearestInMap, m_graph.pose(j)));
		}
	const TPose2D guess = between(nearestInMap, guessInMap);
	const Eigen::Matrix3d covInNearest = rotateCovariance(cov, -nearestInMap.phi);
	// People and doors moved since the old scans: the free-space limit of local registration
	// (as CLocalizer), not the strict one of loop closing.
	TScanMatcherParams mp = m_params.matcher;
	mp.max_free_space_violation = m_params.local.max_free_space_violation;
	std::optional<TScanMatch> m;
	if (!scans.empty())
		m = CScanMatcher(mp).match(CReferenceCloud::fromScans(scans, scansInNearest, mp),
								   m_keyframes[node].scan, guess);
	TMapLink out{{nearest, node, guess, linkInformation(covInNearest, m_params.loop.link_noise),
				  LinkType::LoopClosure},
				 guessInMap,
				 {},
				 !scans.empty()};
	// The old scans were taken at another time: their agreement with a new scan is limited by
	// the loop links' noise floor, as is the correlation's with the match.
	if (m && m->inlierFraction >= m_params.local.min_link_inlier_fraction &&
		disagreementChi2(guess, m->scanInRef,
						 covInNearest + m->cov + m_params.loop.link_noise.floorCovariance()) <=
			kAgreeChi2)
	{
		out.link.toInFrom = m->scanInRef;
		out.link.information = linkInformation(m->cov, m_params.loop.link_noise);
		out.nodeInMap = compose(nearestInMap, m->scanInRef);
	}
	else
		out.problem =
			!m ? "no scan match with the old map around it"
			   : mrpt::format(
					 "its scan match with the old map (%.0f %% inliers, %.2f m, %.1f deg off) "
					 "does not confirm it",
					 100 * m->inlierFraction, translationNorm(between(guess, m->scanInRef)),
					 mrpt::RAD2DEG(between(guess, m->scanInRef).phi));
	return out;
}

// A keyframe of an older session that a scan of this session reuses shows that scan from then
// on, in the grid and in the saved map: where the world changed since (furniture moved, a
// door closed) the map shows the place as it is now, as newer scans replace older ones of the
// same place in the dynamic pose graph of Walcott-Bryant et al. (2012). The scan's laser is
// copied with its sensor pose re-expressed in the keyframe's frame,
//     (node <- sensor) = (node <- robot at the scan) (+) (robot <- sensor),
// so that it reads as the keyframe's own scan from the keyframe's pose. Once per keyframe and
// session, no new node: the map does not grow. The keyframe's points for matching
// (TKeyframe::scan) stay as they were, so this run's trajectory is the same with or without
// the rule (and the loop-closing worker may read them meanwhile); a session that loads the
// saved map matches against the newer scan.
void CMetricMapBuilderLRGC::showNewerScan(size_t node,
										  const mrpt::obs::CObservation2DRangeScan::Ptr& laser,
										  const TPose2D& robotInNode)
{
	auto shown = std::make_shared<mrpt::obs::CObservation2DRangeScan>(*laser);
	shown->sensorPose =
		mrpt::poses::CPose3D(robotInNode.x, robotInNode.y, 0, robotInNode.phi, 0, 0) +
		laser->sensorPose;
	auto frame = mrpt::obs::CSensoryFrame::Create();
	frame->insert(shown);
	TKeyframe& k = m_keyframes[node];
	k.laser = shown;
	k.observations = frame;
	k.session = m_session;
	++m_stats.keyframesRenewed;
}

}  // namespace lrgc
