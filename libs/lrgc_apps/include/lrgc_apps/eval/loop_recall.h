/* Loop recall: how many of the places a robot revisits the map closed a loop at, and how many
 * kept loop links are false (issue 28). One definition for the synthetic worlds, where the
 * truth is exact, and for real logs, where a reference trajectory stands in for it (main's
 * dense run of the same log, ~3 cm on the relations, for its sparse variant).
 *
 *  - Revisit: a keyframe whose reference position lies within `revisitNear_m` (2 m) of that
 *    of a keyframe at least `revisitGap_s` (60 s) older.
 *  - Places: the revisit keyframes in map order, cut into pieces of `placeLength_m` (10 m) of
 *    path (the reference's, summed over consecutive keyframes): a revisit keyframe starts a
 *    new place when the path since the current place's first keyframe is 10 m or more.
 *  - A loop link (LoopClosure, enabled in the final graph) agrees with the reference if its
 *    measurement Z = (from <- to) differs from the reference's relative pose
 *    d = (ref_from^-1 (+) ref_to)^-1 (+) Z by at most `maxXY_m` (0.3 m) and `maxPhi_rad`
 *    (5 deg), or if d^T Omega d <= `maxChi2` (16.27, chi2 3 dof p = 0.001: a corridor match
 *    that states a 1 m std along the corridor is honest, not false). Else it is a false
 *    closure.
 *  - A place is closed when one of its keyframes is the newer end (higher index) of a loop
 *    link that agrees and whose ends are `revisitGap_s` or more apart in time.
 *  - Recall = places closed / places.
 * A reference trajectory is locally right (the dense runs: ~3 cm on relations seconds long)
 * but may be off where its own loops joined (dense Killian: 0.38 m at a revisit, where the
 * sparse run's links were right to 0.04-0.08 m by the dataset's relations). So where ground
 * truth relations (Kuemmerle et al.) join the neighbourhoods of both ends of a link, within
 * `relationReach_s`, the truth is composed from them:
 *     (from <- to) = (ref_from^-1 (+) ref_t1) (+) relation(t1 -> t2) (+) (ref_t2^-1 (+) ref_to)
 * with the relation whose ends lie nearest in time (|t1 - t_from| + |t2 - t_to|, either way
 * round); the reference bridges only those few seconds.
 * Without a reference, relation_truth.h judges by the relations alone (lrgc-eval --loops with
 * --relations and no --reference; the SparseScans tests).
 */
#pragma once

#include <lrgc/pose_graph/PoseGraph.h>
#include <lrgc_apps/eval/relation_metric.h>
#include <mrpt/math/TPose2D.h>

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace lrgc::apps::eval
{
/** One keyframe (graph node) as the recall sees it. */
struct TRecallKeyframe
{
	double t = 0;                   //!< [s] time of its scan
	mrpt::math::TPose2D reference;  //!< (world <- robot) by the truth or the reference [m, rad]
};

struct TLoopRecallParams
{
	double revisitGap_s = 60;   //!< [s] a revisit is at least this much later
	double revisitNear_m = 2;   //!< [m] and this close to the earlier visit
	double placeLength_m = 10;  //!< [m] of path per place
	double maxXY_m = 0.3;       //!< [m] a loop link within this of the reference agrees
	double maxPhi_rad = 5 * M_PI / 180;  //!< [rad] and within this
	double maxChi2 = 16.27;              //!< or within this by its own information
	/** [m] The judge's own position error per relation on its path (relation_truth.h), added
	 * to maxXY_m in quadrature: sqrt(maxXY_m^2 + (k x this)^2) for a path of k relations.
	 * A path of k relations drifts like a random walk of k steps, so a fixed 0.3 m calls
	 * right links false: against the dense runs, 90 % of the sparse logs' revisit paths of k
	 * relations are within 0.02-0.03 m x k (at 15 relations, 10-44 % of them more than 0.3 m
	 * off; doc/generalisation.md, "The relations' judge at its own error"). */
	double maxXYPerRelation_m = 0.03;
	double relationReach_s = 20;  //!< [s] a relation this close to both ends decides
};

/** An enabled loop link set against the reference. */
struct TAuditedLoopLink
{
	std::size_t from = 0, to = 0;                  //!< keyframes
	double offXY_m = 0, offPhi_rad = 0, chi2 = 0;  //!< disagreement with the reference
	bool agrees = false;
	bool byRelation = false;    //!< judged by a ground-truth relation, not the reference
	bool judged = true;         //!< false: the truth is unknown (relation_truth.h)
	bool bridged = false;       //!< by relations, the map bridging an end (relation_truth.h)
	std::size_t relations = 0;  //!< relations on the judge's path (0: by a reference)
	/** Z - truth in from's axes (x [m], y [m], phi [rad]) and the link's information over
	 * them: the calibration of its claimed covariance (linkCalibration). */
	Eigen::Vector3d error = Eigen::Vector3d::Zero();
	Eigen::Matrix3d information = Eigen::Matrix3d::Identity();
};

/** How honest the judged loop links' covariances C = Omega^-1 are against their true errors
 * e (in from's axes). A calibrated link has chi2 = e^T Omega e ~ chi2(3 dof): median 2.37,
 * 5 % above 7.81. Per axis, the squared error normalised by the marginal variance along it,
 * ~ chi2(1 dof) (median 0.455, 1 % above 6.63): the weak axis is the eigenvector of C's
 * translation block with the larger eigenvalue (a corridor's length), the strong axis the
 * other, and the heading. A median well above the calibrated one says the links claim too
 * much along that axis. */
struct TLinkCalibration
{
	struct TAxis
	{
		double median = 0, mean = 0;  //!< of the normalised squared error [-]
		double over99 = 0;            //!< share above chi2(1 dof) 99 % (6.63) [-]
	};
	std::size_t links = 0;  //!< judged links
	double chi2Median = 0;  //!< [-]
	double chi2Over95 = 0;  //!< share above chi2(3 dof) 95 % (7.81) [-]
	TAxis weak, strong, heading;
	double weakStdMedian_m = 0, strongStdMedian_m = 0;  //!< claimed stds [m], medians
	double weakErrMedian_m = 0;                         //!< |error| along the weak axis [m]
};
TLinkCalibration linkCalibration(const std::vector<TAuditedLoopLink>& links);

/** A piece of revisited path. */
struct TRevisitPlace
{
	std::size_t firstKeyframe = 0, lastKeyframe = 0;
	double firstTime_s = 0, lastTime_s = 0;  //!< [s] their scans' times
	bool closed = false;
};

struct TLoopRecall
{
	std::vector<TRevisitPlace> places;
	std::vector<TAuditedLoopLink> loopLinks;  //!< every enabled LoopClosure link
	std::size_t closed = 0;                   //!< places closed
	std::size_t falseClosures = 0;            //!< loop links that disagree
	std::size_t byRelation = 0;               //!< loop links judged by a relation
	std::size_t notJudged = 0;                //!< loop links whose truth is unknown
	/** The link pairs (from, to) that agree, in link order. */
	std::vector<std::pair<std::size_t, std::size_t>> agreeingLinks() const;
	double recall() const { return places.empty() ? 0.0 : double(closed) / places.size(); }
};

/** The true (from <- to) of two keyframes where it is better known than by their reference
 * poses; nothing: the reference's. */
using TTruthBetween = std::function<std::optional<mrpt::math::TPose2D>(
	const TRecallKeyframe& from, const TRecallKeyframe& to)>;

/** What the recall asks of a truth, per keyframe index: is i a revisit; the path [m] from
 * keyframe i - 1 to i; the true (from <- to) of a loop link and whether a relation gave it
 * (nothing: not judged). The evaluateLoopRecall overloads build one. */
struct TRecallJudge
{
	struct TTruth
	{
		mrpt::math::TPose2D toInFrom;
		bool byRelation = false;
		bool bridged = false;
		std::size_t relations = 0;  //!< on the path of relations (0: by a reference)
	};
	std::function<bool(std::size_t)> isRevisit;
	std::function<double(std::size_t)> step_m;
	std::function<std::optional<TTruth>(std::size_t, std::size_t)> between;
};
TLoopRecall evaluateLoopRecall(const lrgc::CPoseGraph& graph,
							   const std::vector<TRecallKeyframe>& keyframes,
							   const TRecallJudge& judge, const TLoopRecallParams& p);

/** Recall and false closures of `graph` (node i = keyframes[i]); see the top of the file.
 * Throws if the graph has more nodes than `keyframes`. */
TLoopRecall evaluateLoopRecall(const lrgc::CPoseGraph& graph,
							   const std::vector<TRecallKeyframe>& keyframes,
							   const TLoopRecallParams& p = {},
							   const TTruthBetween& truthBetween = {});

/** truthBetween from ground-truth relations and the reference trajectory (see the top). */
TTruthBetween truthFromRelations(std::vector<TRelation> relations, CTrajectory2D reference,
								 double reach_s, double tolerance_s = 1e-5);

/** The keyframes of an lrgc-slam output folder (map.simplemap.gz: its scans' timestamps) with
 * the reference pose at each scan's time (CTrajectory2D::poseAt: the pose of equal timestamp
 * within `tolerance_s`, else interpolated), and its graph (graph.lrgc). An empty `reference`
 * gives the map's own keyframe poses instead (for relation_truth.h's bridges). Throws, naming
 * the file, if one is missing or unreadable, a node has no scan or a scan's time lies outside
 * the reference. */
struct TRecallInputs
{
	lrgc::CPoseGraph graph;
	std::vector<TRecallKeyframe> keyframes;
	CTrajectory2D reference;
};
TRecallInputs loadRecallInputs(const std::string& outputDir, const std::string& reference,
							   double tolerance_s = 1e-5);

/** Text lines of the report: figures, the unclosed places, the false closures. */
std::string recallReport(const TLoopRecall& r);

/** One text line of linkCalibration over r's judged loop links. */
std::string calibrationReport(const TLoopRecall& r);

}  // namespace lrgc::apps::eval
