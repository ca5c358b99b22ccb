/* Stress variants of the glass-and-railings world (issue 28 items 1 and 2): the long-range
 * laser's properties pushed further than GlassBuilding does, run through the whole map
 * builder with exact ground truth. Nothing is written: each run prints its figures.
 *
 * Worlds: `building` is GlassBuilding's (makeGlassBuildingWorld(5, glass), 100 x 60 m, laps of
 * the 178 m loop around the courtyard block); `atrium` is makeGlassAtriumWorld (160 x 100 m
 * by default, wide halls around a railed atrium, laps of the halls' 392 m centre loop);
 * `museum` is makeMuseumWorld (64 x 28 m, two galleries lined with identical niches, laps of
 * the 136 m loop around their central block).
 *
 * Figures per run (as GlassBuilding's, tests/glass_building_test.cpp):
 *  - unmatched scans; relations from every fifth scan to the scans about 1, 5 and 9.8 s later,
 *    the share off by more than 2 deg (and the count over 5 deg);
 *  - loop recall (10 m places of keyframes within 2 m of one at least 60 s older, closed by a
 *    true loop link kept in the final graph) and false closures (kept links off the truth);
 *  - the loop worker's searches: run, rejected by the filters / the match / the back-end,
 *    deferred (shed), merged, dropped; far searches and the loops they closed;
 *  - relation error [m]: mean translational error of the short relations, and of long ones
 *    (every 10th scan to every 10th scan at least 60 s later); worst position error of the
 *    map and of dead reckoning (both from the first pose).
 *
 * Run: build/bin/glass_stress world=atrium laps=3 seeds="1 2 3" [odo=2] [bias=1] [glass=0.1]
 *      [dropout=0.3] [period=0.7] [step=0.4] [loops=1] [hall=12] [length=160] [width=100]
 *      [ini=params.ini] [places=1] [links=1] [turns=2] [around=K] [maxturn=80] [range=80]
 *      [people=25] [scale=1.04]
 * (odo: odometry noise, times the default model; bias: the odometry turns that many times the
 * true turn; glass: share of beams a pane returns; dropout: TLaserSimParams::maxRangeDropRate;
 * period [s] and step [m] between scans; ini: lrgc's parameters; places=1 lists the revisited
 * places left unclosed; links=1 lists the kept loop links whose chi2 by the truth is above
 * 16.27 (their error and claimed stds along the weak and strong axes, loop_recall.h);
 * turns=D lists consecutive keyframes whose relative heading in the final graph is off the
 * truth's by more than D deg (with loops=0: local registration's own steps); around=K lists
 * every link with an end in keyframes K-4 .. K+4, what it claims against the truth; maxturn:
 * the largest turn in place between two scans [deg] (0: 34.4, 0.6 rad); range: the laser's
 * maximum range [m]; people: that many people walking (CCrowd, seed 200 + s); scale: the
 * odometry travels that many times the true translation. Seed s:
 * world seed s (atrium, museum), trajectory seed 60 + s, laser seed s.)
 */
#include <lrgc/common/se2.h>
#include <lrgc_apps/eval/loop_recall.h>
#include <lrgc_apps/eval/relation_metric.h>

#include <mrpt/config/CConfigFile.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <chrono>
#include <cstdio>
#include <map>
#include <sstream>
#include <string>

#include "synthetic_eval.h"

using namespace lrgc::test;
using lrgc::CMetricMapBuilderLRGC;
using mrpt::math::TPose2D;
namespace ev = lrgc::apps::eval;

namespace
{
struct TOptions
{
	std::map<std::string, std::string> kv{
		{"world", "atrium"}, {"laps", "3"},    {"seeds", "1"},     {"odo", "2"},
		{"bias", "1"},       {"glass", "0.1"}, {"dropout", "0.3"}, {"period", "0.7"},
		{"step", "0.4"},     {"loops", "1"},   {"hall", "12"},     {"length", "160"},
		{"width", "100"},    {"ini", ""},      {"places", "0"},    {"links", "0"},
		{"turns", "0"},      {"around", "-1"}, {"maxturn", "0"},   {"range", "80"},
		{"people", "0"},     {"scale", "1"}};
	double num(const std::string& k) const { return std::stod(kv.at(k)); }
};

TTrajectory laps(const TOptions& o, uint32_t seed)
{
	std::vector<Eigen::Vector2d> lap, wp;
	if (o.kv.at("world") == "building")
	{
		lap = {{78, 12}, {78, 45}, {22, 45}, {22, 12}};
		wp = {{22, 12}};
	}
	else if (o.kv.at("world") == "museum")
	{
		lap = {{58, 6}, {58, 22}, {6, 22}, {6, 6}};  // makeMuseumWorld's 64 x 28 m
		wp = {{14, 6}};
	}
	else
	{
		const double c = 10 + o.num("hall") / 2;  // the halls' centre lines
		const double L = o.num("length"), H = o.num("width");
		lap = {{L - c, c}, {L - c, H - c}, {c, H - c}, {c, c}};
		wp = {{30, c}};
	}
	for (int i = 0; i < int(o.num("laps")); ++i) wp.insert(wp.end(), lap.begin(), lap.end());
	wp.push_back(wp[0] + Eigen::Vector2d(28, 0));
	TOdometryNoise noise;
	const double k = o.num("odo");
	noise.a1 *= k, noise.a2 *= k, noise.a3 *= k, noise.a4 *= k;
	const double maxTurn = o.num("maxturn") > 0 ? mrpt::DEG2RAD(o.num("maxturn")) : 0.6;
	TTrajectory tr = makeTrajectory(wp, o.num("step"), noise, seed, maxTurn);
	// Gyro and wheel scale errors: the odometry turns `bias` times the true turn and travels
	// `scale` times the true translation.
	scaleOdometry(tr, o.num("bias"), o.num("scale"));
	return tr;
}

/** Kept loop links whose chi2 by the truth exceeds 16.27: error and claimed stds along the
 * weak and strong axes of their translation covariance, and heading. */
void printOverconfidentLinks(const ev::TLoopRecall& recall, const CMetricMapBuilderLRGC& b)
{
	for (const auto& l : recall.loopLinks)
	{
		if (!l.judged || l.chi2 <= 16.27) continue;
		const Eigen::Matrix3d C = l.information.inverse();
		const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(C.topLeftCorner<2, 2>());
		const Eigen::Vector2d e = l.error.head<2>();
		std::printf(
			"  link %zu -> %zu (scans %zu -> %zu): chi2 %.1f, weak axis %.3f m off (std %.3f), "
			"strong %.3f m (std %.3f), heading %.2f deg (std %.2f)\n",
			l.from, l.to, b.keyframes()[l.from].scanIndex, b.keyframes()[l.to].scanIndex,
			l.chi2, std::abs(es.eigenvectors().col(1).dot(e)), std::sqrt(es.eigenvalues()(1)),
			std::abs(es.eigenvectors().col(0).dot(e)), std::sqrt(es.eigenvalues()(0)),
			mrpt::RAD2DEG(l.error.z()), mrpt::RAD2DEG(std::sqrt(C(2, 2))));
	}
}

/** Consecutive keyframes (k-1, k) whose relative heading in the graph is off the truth's by
 * more than `maxDeg`: where registration turned the map. */
void printTurnedSteps(const CMetricMapBuilderLRGC& b, const TTrajectory& tr, double maxDeg)
{
	const auto& kf = b.keyframes();
	for (size_t k = 1; k < kf.size(); ++k)
	{
		const TPose2D est = lrgc::between(b.graph().pose(k - 1), b.graph().pose(k));
		const TPose2D tru = lrgc::between(tr.truePoses.at(kf[k - 1].scanIndex),
										  tr.truePoses.at(kf[k].scanIndex));
		const double off = mrpt::RAD2DEG(mrpt::math::wrapToPi(est.phi - tru.phi));
		if (std::abs(off) <= maxDeg) continue;
		const auto& t = tr.truePoses.at(kf[k].scanIndex);
		std::printf(
			"  turned: keyframes %zu -> %zu (scans %zu -> %zu), %.2f deg off (true turn %.1f "
			"deg, step %.2f m off), at (%.1f, %.1f, %.0f deg)\n",
			k - 1, k, kf[k - 1].scanIndex, kf[k].scanIndex, off, mrpt::RAD2DEG(tru.phi),
			std::hypot(est.x - tru.x, est.y - tru.y), t.x, t.y, mrpt::RAD2DEG(t.phi));
	}
}

/** Every link (enabled or not) with an end in keyframes [k - 4, k + 4]: its type, what it
 * claims against the truth (the error of toInFrom, in the from node's frame) and its stds, the
 * chi2 of that error by its information, and the final graph's error over the same pair. */
void printLinksAround(const CMetricMapBuilderLRGC& b, const TTrajectory& tr, size_t k)
{
	const auto& kf = b.keyframes();
	const auto& g = b.graph();
	for (size_t id = 0; id < g.numLinks(); ++id)
	{
		const auto& l = g.link(id);
		const auto near = [k](size_t n) { return n + 4 >= k && n <= k + 4; };
		if (!near(l.from) && !near(l.to)) continue;
		const TPose2D tru = lrgc::between(tr.truePoses.at(kf[l.from].scanIndex),
										  tr.truePoses.at(kf[l.to].scanIndex));
		const TPose2D est = lrgc::between(g.pose(l.from), g.pose(l.to));
		const Eigen::Vector3d e(l.toInFrom.x - tru.x, l.toInFrom.y - tru.y,
								mrpt::math::wrapToPi(l.toInFrom.phi - tru.phi));
		const Eigen::Matrix3d C = l.information.inverse();
		std::printf(
			"  link %zu %s %zu -> %zu%s: claims (%.3f, %.3f, %.2f deg), off (%.3f, %.3f, %.2f "
			"deg), std (%.3f, %.3f, %.2f deg), chi2 %.1f; graph off (%.3f, %.3f, %.2f deg)\n",
			id, lrgc::toString(l.type), l.from, l.to, g.isLinkEnabled(id) ? "" : " (disabled)",
			l.toInFrom.x, l.toInFrom.y, mrpt::RAD2DEG(l.toInFrom.phi), e.x(), e.y(),
			mrpt::RAD2DEG(e.z()), std::sqrt(C(0, 0)), std::sqrt(C(1, 1)),
			mrpt::RAD2DEG(std::sqrt(C(2, 2))), e.dot(l.information * e), est.x - tru.x,
			est.y - tru.y, mrpt::RAD2DEG(mrpt::math::wrapToPi(est.phi - tru.phi)));
	}
	const TPose2D& t0 = tr.truePoses.front();
	for (size_t n = k >= 4 ? k - 4 : 0; n <= k + 4 && n < kf.size(); ++n)
	{
		const TPose2D d =
			lrgc::between(tr.truePoses.at(kf[n].scanIndex), lrgc::compose(t0, g.pose(n)));
		std::printf("  keyframe %zu (scan %zu): %.3f m, %.2f deg off the truth\n", n,
					kf[n].scanIndex, std::hypot(d.x, d.y), mrpt::RAD2DEG(d.phi));
	}
}

void runOne(const TOptions& o, uint32_t seed)
{
	const std::string& name = o.kv.at("world");
	TGlassAtriumShape shape;
	shape.hall = o.num("hall"), shape.length = o.num("length"), shape.width = o.num("width");
	shape.glassReturn = o.num("glass");
	const CSyntheticWorld world = name == "building" ? makeGlassBuildingWorld(5, o.num("glass"))
								  : name == "museum" ? makeMuseumWorld(seed)
													 : makeGlassAtriumWorld(seed, shape);
	const TTrajectory tr = laps(o, 60 + seed);
	const double clearance = minClearance(world, tr.truePoses);
	lrgc::TLRGCParams p;
	if (!o.kv.at("ini").empty())
		p.loadFromConfigFile(mrpt::config::CConfigFile(o.kv.at("ini")));
	p.builder.loop_closing = o.num("loops") != 0;
	CMetricMapBuilderLRGC builder(p);
	builder.setMinLoggingLevel(mrpt::system::LVL_ERROR);
	TSyntheticRunOptions laser =
		longRangeSick(o.num("period"), o.num("range"), o.num("dropout"), seed);
	// People walking anywhere in the world's bounding box (CCrowd keeps them off the robot).
	const CCrowd crowd(world.bounds(), int(o.num("people")), 200 + seed);
	if (o.num("people") > 0) laser.crowd = &crowd;
	const auto t0 = std::chrono::steady_clock::now();
	feedBuilder(builder, world, tr, laser);
	const double secs =
		std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

	const double period = o.num("period");
	const auto& est = builder.trajectory();
	const auto shortRel = evaluateOnTruth(est, truthRelations(tr.truePoses, period, false));
	const auto longRel = evaluateOnTruth(est, truthRelations(tr.truePoses, period, true));
	const auto recall = truthLoopRecall(builder, tr.truePoses, period);
	const auto err = trajectoryError(builder.trajectory(), tr.truePoses);
	std::vector<TPose2D> odo;
	for (const auto& q : tr.odometryPoses)
		odo.push_back(lrgc::between(tr.odometryPoses.front(), q));
	const auto odoErr = trajectoryError(odo, tr.truePoses);
	const auto& st = builder.stats();
	const auto& ls = builder.loopCloserStats();
	std::printf(
		"seed %u: %zu scans (%zu unmatched, %zu keyframes re-matched at the end), %zu kf; "
		"short %zu, >2deg %zu (%.2f %%), >5deg "
		"%zu; recall %zu / %zu, false %zu; searches %zu (filters %zu, match %zu, back-end "
		"%zu), shed %zu, merged %zu, dropped %zu; far %zu (closed %zu); closures %zu; "
		"rel err short %.4f m, long %.3f m (max %.2f); map worst %.2f m %.1f deg, odometry "
		"worst %.1f m %.1f deg; clearance %.2f m; %.0f s\n",
		seed, st.scans, st.unmatchedScans, st.keyframesRematched, st.keyframes,
		shortRel.shortCount, shortRel.shortOver2deg, 100 * shortRel.shortOver2degShare(),
		shortRel.shortOver5deg, recall.closed, recall.places.size(), recall.falseClosures,
		ls.attempts, ls.rejectedByFilters, ls.rejectedByMatch, ls.rejectedByBackEnd,
		ls.searchesShed, ls.searchesMerged, ls.droppedKeyframes.size(), ls.farSearches,
		ls.farClosures, st.loopClosures, shortRel.trans_m.mean, longRel.trans_m.mean,
		longRel.trans_m.max, err.maxXY, mrpt::RAD2DEG(err.maxPhi), odoErr.maxXY,
		mrpt::RAD2DEG(odoErr.maxPhi), clearance, secs);
	if (o.num("places") != 0)
		for (const auto& pl : recall.places)
			if (!pl.closed)
			{
				const auto& a = tr.truePoses[builder.keyframes()[pl.firstKeyframe].scanIndex];
				const auto& b = tr.truePoses[builder.keyframes()[pl.lastKeyframe].scanIndex];
				std::printf(
					"  not closed: keyframes %zu-%zu, true (%.1f, %.1f) to (%.1f, %.1f)\n",
					pl.firstKeyframe, pl.lastKeyframe, a.x, a.y, b.x, b.y);
			}
	std::printf("  %s", ev::calibrationReport(recall).c_str());
	if (o.num("links") != 0) printOverconfidentLinks(recall, builder);
	if (o.num("turns") != 0) printTurnedSteps(builder, tr, o.num("turns"));
	if (o.num("around") >= 0)
	{
		std::printf("  map worst at scan %zu\n", err.worstIndex);
		printLinksAround(builder, tr, size_t(o.num("around")));
	}
	for (const auto& l : recall.loopLinks)
		if (l.judged && !l.agrees)
			std::printf(
				"  false closure: keyframe %zu -> %zu (scans %zu -> %zu), %.2f m, %.1f "
				"deg off, chi2 %.1f\n",
				l.from, l.to, builder.keyframes()[l.from].scanIndex,
				builder.keyframes()[l.to].scanIndex, l.offXY_m, mrpt::RAD2DEG(l.offPhi_rad),
				l.chi2);
	std::fflush(stdout);
}
}  // namespace

int main(int argc, char** argv)
{
	TOptions o;
	for (int i = 1; i < argc; ++i)
	{
		const std::string a = argv[i];
		const auto eq = a.find('=');
		if (eq == std::string::npos || !o.kv.count(a.substr(0, eq)))
		{
			std::fprintf(stderr, "unknown argument '%s'\n", argv[i]);
			return 2;
		}
		o.kv[a.substr(0, eq)] = a.substr(eq + 1);
	}
	std::printf("glass_stress");
	for (const auto& [k, v] : o.kv) std::printf(" %s=%s", k.c_str(), v.c_str());
	std::printf("\n");
	std::istringstream seeds(o.kv.at("seeds"));
	for (uint32_t s; seeds >> s;) runOne(o, s);
	return 0;
}
