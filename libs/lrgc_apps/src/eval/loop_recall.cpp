/* Loop recall against a truth or a reference trajectory (definition in loop_recall.h). */
#include "lrgc_apps/eval/loop_recall.h"

#include "lrgc_apps/SavedMap.h"
#include "lrgc_apps/eval/trajectory.h"

#include <lrgc/common/OrderStatistic.h>
#include <lrgc/common/se2.h>
#include <mrpt/core/format.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3DPDF.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

namespace lrgc::apps::eval
{
namespace
{
Eigen::Vector2d position(const TRecallKeyframe& k)
{
	return {k.reference.x, k.reference.y};
}

/** e = Z - truth in from's axes: translation [m], heading [rad] and chi2; no truth: not
 * judged. */
TAuditedLoopLink audit(const lrgc::TLink& l, const std::optional<TRecallJudge::TTruth>& truth,
					   const TLoopRecallParams& p)
{
	TAuditedLoopLink a;
	a.from = l.from, a.to = l.to;
	a.judged = truth.has_value();
	if (!truth) return a;
	a.byRelation = truth->byRelation;
	a.bridged = truth->bridged;
	a.relations = truth->relations;
	// The link's information is over (x, y, phi) of `to` in the axes of `from` (a scan match's
	// covariance, lrgc/pose_graph/PoseGraph.h), so the error is the difference of the two poses
	// in those axes; v(truth^-1 (+) Z) would turn it into the truth's own axes, which for a
	// link turned by 90 deg reads the information with x and y swapped (doc/back-end.md).
	const mrpt::math::TPose2D& z = l.toInFrom;
	const mrpt::math::TPose2D& t = truth->toInFrom;
	const Eigen::Vector3d e(z.x - t.x, z.y - t.y, mrpt::math::wrapToPi(z.phi - t.phi));
	a.offXY_m = e.head<2>().norm();
	a.offPhi_rad = std::abs(e.z());
	a.chi2 = e.dot(l.information * e);
	a.error = e;
	a.information = l.information;
	const double maxXY = std::hypot(p.maxXY_m, p.maxXYPerRelation_m * double(a.relations));
	a.agrees = (a.offXY_m <= maxXY && a.offPhi_rad <= p.maxPhi_rad) || a.chi2 <= p.maxChi2;
	return a;
}

/** Is keyframe i within revisitNear_m of one at least revisitGap_s older (by the reference)? */
bool isRevisit(const std::vector<TRecallKeyframe>& kfs, std::size_t i,
			   const TLoopRecallParams& p)
{
	for (std::size_t j = 0; j < i; ++j)
		if (kfs[i].t - kfs[j].t >= p.revisitGap_s &&
			(position(kfs[i]) - position(kfs[j])).norm() < p.revisitNear_m)
			return true;
	return false;
}

/** The places (loop_recall.h), each closed if it holds one of `closedKf`. */
std::vector<TRevisitPlace> revisitPlaces(const std::vector<TRecallKeyframe>& kfs,
										 const std::set<std::size_t>& closedKf,
										 const TRecallJudge& judge, const TLoopRecallParams& p)
{
	std::vector<TRevisitPlace> places;
	double placeStart = -1, travelled = 0;  // [m] of path
	for (std::size_t i = 0; i < kfs.size(); ++i)
	{
		if (i > 0) travelled += judge.step_m(i);
		if (!judge.isRevisit(i)) continue;
		if (placeStart < 0 || travelled - placeStart >= p.placeLength_m)
		{
			places.push_back({i, i, kfs[i].t, kfs[i].t, false});
			placeStart = travelled;
		}
		places.back().lastKeyframe = i;
		places.back().lastTime_s = kfs[i].t;
		places.back().closed = places.back().closed || closedKf.count(i) > 0;
	}
	return places;
}
}  // namespace

std::vector<std::pair<std::size_t, std::size_t>> TLoopRecall::agreeingLinks() const
{
	std::vector<std::pair<std::size_t, std::size_t>> out;
	for (const auto& l : loopLinks)
		if (l.agrees) out.emplace_back(l.from, l.to);
	return out;
}

TLoopRecall evaluateLoopRecall(const lrgc::CPoseGraph& graph,
							   const std::vector<TRecallKeyframe>& keyframes,
							   const TRecallJudge& judge, const TLoopRecallParams& p)
{
	if (graph.numNodes() > keyframes.size())
		throw std::invalid_argument(mrpt::format(
			"loop recall: the graph has %zu nodes but only %zu keyframes are given",
			graph.numNodes(), keyframes.size()));
	TLoopRecall r;
	std::set<std::size_t> closedKf;  // the newer end of each agreeing loop link
	for (std::size_t id = 0; id < graph.numLinks(); ++id)
	{
		const auto& l = graph.link(id);
		if (l.type != lrgc::LinkType::LoopClosure || !graph.isLinkEnabled(id)) continue;
		r.loopLinks.push_back(audit(l, judge.between(l.from, l.to), p));
		const auto& a = r.loopLinks.back();
		r.byRelation += a.byRelation ? 1 : 0;
		if (!a.judged)
			++r.notJudged;
		else if (!a.agrees)
			++r.falseClosures;
		else if (std::abs(keyframes[l.from].t - keyframes[l.to].t) >= p.revisitGap_s)
			closedKf.insert(std::max(l.from, l.to));
	}
	r.places = revisitPlaces(keyframes, closedKf, judge, p);
	for (const auto& pl : r.places) r.closed += pl.closed ? 1 : 0;
	return r;
}

TLoopRecall evaluateLoopRecall(const lrgc::CPoseGraph& graph,
							   const std::vector<TRecallKeyframe>& keyframes,
							   const TLoopRecallParams& p, const TTruthBetween& truthBetween)
{
	TRecallJudge judge;
	judge.isRevisit = [&](std::size_t i) { return isRevisit(keyframes, i, p); };
	judge.step_m = [&](std::size_t i)
	{ return (position(keyframes[i]) - position(keyframes[i - 1])).norm(); };
	judge.between = [&](std::size_t from, std::size_t to)
	{
		std::optional<mrpt::math::TPose2D> truth;
		if (truthBetween) truth = truthBetween(keyframes.at(from), keyframes.at(to));
		if (truth) return std::optional<TRecallJudge::TTruth>({*truth, true});
		return std::optional<TRecallJudge::TTruth>(
			{lrgc::between(keyframes.at(from).reference, keyframes.at(to).reference), false});
	};
	return evaluateLoopRecall(graph, keyframes, judge, p);
}

TRecallInputs loadRecallInputs(const std::string& outputDir, const std::string& reference,
							   double tolerance_s)
{
	const TSavedMap map = loadSavedMap(outputDir, "--loops");
	if (!map.graph)
		throw std::runtime_error("--loops '" + outputDir +
								 "': the folder has no graph.lrgc (the loop links)");
	const CTrajectory2D ref =
		reference.empty() ? CTrajectory2D() : CTrajectory2D::loadFromFile(reference);
	TRecallInputs in;
	in.graph = map.graph->graph;
	in.reference = ref;
	for (std::size_t i = 0; i < map.keyframes.size(); ++i)
	{
		const auto [posePDF, sf] = map.keyframes.get(i);
		mrpt::obs::CObservation2DRangeScan::Ptr scan;
		if (sf) scan = sf->getObservationByClass<mrpt::obs::CObservation2DRangeScan>();
		if (!scan)
			throw std::runtime_error(mrpt::format("--loops '%s': keyframe %zu holds no 2D scan",
												  outputDir.c_str(), i));
		const double t = mrpt::Clock::toDouble(scan->timestamp);
		if (reference.empty())
		{
			in.keyframes.push_back({t, mrpt::poses::CPose2D(posePDF->getMeanVal()).asTPose()});
			continue;
		}
		const auto pose = ref.poseAt(t, tolerance_s);
		if (!pose)
			throw std::runtime_error(
				mrpt::format("--reference '%s': no pose at %.6f s (keyframe %zu of '%s')",
							 reference.c_str(), t, i, outputDir.c_str()));
		in.keyframes.push_back({t, pose->pose});
	}
	return in;
}

TTruthBetween truthFromRelations(std::vector<TRelation> relations, CTrajectory2D reference,
								 double reach_s, double tolerance_s)
{
	return [rel = std::move(relations), ref = std::move(reference), reach_s, tolerance_s](
			   const TRecallKeyframe& from,
			   const TRecallKeyframe& to) -> std::optional<mrpt::math::TPose2D>
	{
		const TRelation* best = nullptr;
		bool swapped = false;
		double bestGap = 2 * reach_s;
		for (const auto& r : rel)
			for (const bool sw : {false, true})
			{
				const double g1 = std::abs((sw ? r.t2 : r.t1) - from.t);
				const double g2 = std::abs((sw ? r.t1 : r.t2) - to.t);
				if (g1 <= reach_s && g2 <= reach_s && g1 + g2 < bestGap)
					best = &r, swapped = sw, bestGap = g1 + g2;
			}
		if (!best) return std::nullopt;
		const auto p1 = ref.poseAt(best->t1, tolerance_s),
				   p2 = ref.poseAt(best->t2, tolerance_s);
		if (!p1 || !p2) return std::nullopt;
		// (t1 <- t2) by the relation; (from <- t1) and (t2 <- to) by the reference.
		const auto motion = swapped ? lrgc::inverse(best->motion) : best->motion;
		const auto& a = swapped ? p2->pose : p1->pose;
		const auto& b = swapped ? p1->pose : p2->pose;
		return lrgc::compose(lrgc::compose(lrgc::between(from.reference, a), motion),
							 lrgc::between(b, to.reference));
	};
}

namespace
{
/** [0 for none] The upper median of a copy of v (lrgc::upperMedian reorders its sample). */
double median(std::vector<double> v)
{
	return v.empty() ? 0 : lrgc::upperMedian(v);
}

TLinkCalibration::TAxis axisStats(const std::vector<double>& n2)
{
	TLinkCalibration::TAxis a;
	if (n2.empty()) return a;
	a.median = median(n2);
	for (const double v : n2)
	{
		a.mean += v / n2.size();
		a.over99 += v > 6.63 ? 1.0 : 0.0;
	}
	a.over99 /= n2.size();
	return a;
}
}  // namespace

TLinkCalibration linkCalibration(const std::vector<TAuditedLoopLink>& links)
{
	TLinkCalibration c;
	std::vector<double> chi2, weak, strong, heading, weakStd, strongStd, weakErr;
	for (const auto& l : links)
	{
		if (!l.judged) continue;
		const Eigen::Matrix3d C = l.information.inverse();
		const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(C.topLeftCorner<2, 2>());
		// Eigenvalues ascending: column 1 is the weak axis.
		const Eigen::Vector2d exy = l.error.head<2>();
		const double ew = es.eigenvectors().col(1).dot(exy),
					 es0 = es.eigenvectors().col(0).dot(exy);
		chi2.push_back(l.chi2);
		weak.push_back(ew * ew / es.eigenvalues()(1));
		strong.push_back(es0 * es0 / es.eigenvalues()(0));
		heading.push_back(l.error.z() * l.error.z() / C(2, 2));
		weakStd.push_back(std::sqrt(es.eigenvalues()(1)));
		strongStd.push_back(std::sqrt(es.eigenvalues()(0)));
		weakErr.push_back(std::abs(ew));
	}
	c.links = chi2.size();
	if (chi2.empty()) return c;
	c.chi2Median = median(chi2);
	for (const double v : chi2) c.chi2Over95 += v > 7.81 ? 1.0 / chi2.size() : 0.0;
	c.weak = axisStats(weak);
	c.strong = axisStats(strong);
	c.heading = axisStats(heading);
	c.weakStdMedian_m = median(weakStd);
	c.strongStdMedian_m = median(strongStd);
	c.weakErrMedian_m = median(weakErr);
	return c;
}

std::string calibrationReport(const TLoopRecall& r)
{
	const TLinkCalibration c = linkCalibration(r.loopLinks);
	if (c.links == 0) return "loop-link calibration: no judged loop link\n";
	const auto axis = [](const char* name, const TLinkCalibration::TAxis& a) {
		return mrpt::format("%s %.2f / %.2f / %.0f %%", name, a.median, a.mean, 100 * a.over99);
	};
	return mrpt::format(
			   "loop-link calibration over %zu judged links: chi2 median %.2f (calibrated "
			   "2.37), %.0f %% above 7.81 (5 %%); per axis, normalised squared error median / "
			   "mean / share above 6.63 (calibrated 0.45 / 1 / 1 %%): ",
			   c.links, c.chi2Median, 100 * c.chi2Over95) +
		   axis("weak", c.weak) + ", " + axis("strong", c.strong) + ", " +
		   axis("heading", c.heading) +
		   mrpt::format(
			   "; claimed std median weak %.3f m, strong %.3f m; weak-axis error "
			   "median %.3f m\n",
			   c.weakStdMedian_m, c.strongStdMedian_m, c.weakErrMedian_m);
}

std::string recallReport(const TLoopRecall& r)
{
	std::string s = mrpt::format(
		"loop recall: %zu of %zu revisited places closed (%.1f %%); %zu loop links kept (%zu "
		"judged by a relation), %zu false closures\n",
		r.closed, r.places.size(), 100 * r.recall(), r.loopLinks.size(), r.byRelation,
		r.falseClosures);
	if (r.notJudged > 0)
		s += mrpt::format("  %zu loop links not judged (their truth unknown)\n", r.notJudged);
	for (const auto& pl : r.places)
		if (!pl.closed)
			s += mrpt::format("  not closed: keyframes %zu-%zu (%.6f-%.6f s)\n",
							  pl.firstKeyframe, pl.lastKeyframe, pl.firstTime_s, pl.lastTime_s);
	for (const auto& l : r.loopLinks)
		if (l.judged && !l.agrees)
			s += mrpt::format(
				"  false closure: keyframe %zu -> %zu, %.2f m, %.1f deg off, chi2 %.1f (by the "
				"%s)\n",
				l.from, l.to, l.offXY_m, l.offPhi_rad * 180 / M_PI, l.chi2,
				!(l.byRelation || l.bridged)
					? "reference"
					: mrpt::format("relations: %zu on the path%s", l.relations,
								   l.bridged ? ", a map bridge" : "")
						  .c_str());
	return s;
}

}  // namespace lrgc::apps::eval
