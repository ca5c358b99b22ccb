/* Every scan's pose final (issue 28 item 4): full SLAM in a 70 x 45 m hall with 25 people
 * walking, an 80 m laser, two laps so the loop closes, exact ground truth.
 *
 * The figures are per scan, after the best rigid alignment of the estimate to the truth
 * (least squares over all scans, as an ATE): the rmse, the worst scan, and the worst scan
 * against its neighbours (its error minus the median error of the 10 scans around it), which
 * catches a single scan left off while the map is right; the same per lap (the first ends
 * at (6, 6)), and the worst of the first lap's first 10 m (40 scans), which only the
 * chain holds when no revisit links it.
 */
#include <gtest/gtest.h>
#include <lrgc/common/se2.h>
#include <lrgc/scan_matching/ReferenceCloud.h>
#include <lrgc/scan_matching/ScanMatcher.h>
#include <lrgc_apps/eval/loop_recall.h>
#include <lrgc_apps/eval/trajectory_error.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <sstream>
#include <stdexcept>

#include "synthetic_run.h"

using namespace lrgc::test;
using lrgc::CMetricMapBuilderLRGC;
using mrpt::math::TPose2D;

namespace
{
/** Per-scan position errors [m] after the least-squares rigid alignment of the estimate's
 * positions onto the truth's (lrgc-eval's bestFitRigid2D, as its ATE). */
std::vector<double> alignedErrors(const lrgc::TTrajectory& est,
								  const std::vector<TPose2D>& truth)
{
	std::vector<TPose2D> poses;
	for (const auto& s : est) poses.push_back(s.robotInMap);
	const TPose2D T = lrgc::apps::eval::bestFitRigid2D(poses, truth);
	std::vector<double> err(truth.size());
	for (size_t k = 0; k < truth.size(); ++k)
		err[k] = lrgc::translationNorm(lrgc::between(truth[k], lrgc::compose(T, poses[k])));
	return err;
}

struct TScanOutliers
{
	double rmse = 0, worst = 0;
	size_t worstIndex = 0;
	double worstAboveNeighbours = 0;  //!< max_k err_k - median(err of the 10 scans around k)
	size_t isolatedIndex = 0;
};

/** The figures of scans [first, last) of `err`; neighbours are looked for in the same range. */
TScanOutliers scanOutliers(const std::vector<double>& err, size_t first, size_t last)
{
	TScanOutliers o;
	double sum2 = 0;
	for (size_t k = first; k < last; ++k)
	{
		sum2 += err[k] * err[k];
		if (err[k] > o.worst) o.worst = err[k], o.worstIndex = k;
		std::vector<double> around;
		for (size_t j = k >= first + 5 ? k - 5 : first; j <= std::min(last - 1, k + 5); ++j)
			if (j != k) around.push_back(err[j]);
		std::nth_element(around.begin(), around.begin() + around.size() / 2, around.end());
		const double above = err[k] - around[around.size() / 2];
		if (above > o.worstAboveNeighbours) o.worstAboveNeighbours = above, o.isolatedIndex = k;
	}
	o.rmse = std::sqrt(sum2 / double(last - first));
	return o;
}

/** Two laps of a 60 x 33 m loop between the pillar rows of makeOpenHallWorld(.., 70, 45, ..)
 * (pillars at x = 5, 15, ... 65 in the rows y = 11.25 and 33.75, at x = 10, ... 60 in
 * y = 22.5, radius 0.3 m), 0.25 m a step; the first lap ends at (6, 6). Every leg keeps
 * 0.7 m or more from a pillar's surface: lap 2's west leg runs at x = 4 (until task
 * `crowd4` at x = 5, through the pillars at (5, 33.75) and (5, 11.25)). */
TTrajectory hallLoops(uint32_t trajectorySeed)
{
	return makeTrajectory(
		{{4, 5}, {64, 5}, {64, 39}, {6, 39}, {6, 6}, {64, 6}, {64, 38}, {4, 38}, {4, 8}}, 0.25,
		TOdometryNoise{}, trajectorySeed);
}

/** The seeds CrowdedHall runs: LRGC_HALL_SEEDS (e.g. "1 2 3 4 5 6 7 8"), 1 and 2 if unset. */
std::vector<uint32_t> hallSeeds()
{
	std::vector<uint32_t> seeds;
	if (const char* env = std::getenv("LRGC_HALL_SEEDS"); env && *env)
	{
		std::istringstream in(env);
		for (uint32_t s; in >> s;) seeds.push_back(s);
		if (!in.eof() || seeds.empty())
			throw std::invalid_argument(std::string("LRGC_HALL_SEEDS: not a list of seeds: '") +
										env + "'");
	}
	else
		seeds = {1, 2};
	return seeds;
}
}  // namespace

/** Index of the first pose of `truth` at `(x, y)` (the end of the first lap). */
size_t firstPoseAt(const std::vector<TPose2D>& truth, double x, double y)
{
	for (size_t k = 0; k < truth.size(); ++k)
		if (std::hypot(truth[k].x - x, truth[k].y - y) < 1e-9) return k;
	return truth.size();
}

/** The kept loop links' calibration against the exact truth (lrgc_apps/eval/loop_recall.h,
 * as lrgc-eval --loops reports it for real logs). */
void printLoopCalibration(const CMetricMapBuilderLRGC& builder,
						  const std::vector<TPose2D>& truth, double scanPeriod)
{
	std::vector<lrgc::apps::eval::TRecallKeyframe> kfs;
	for (const auto& kf : builder.keyframes())
		kfs.push_back({scanPeriod * double(kf.scanIndex), truth.at(kf.scanIndex)});
	const auto recall = lrgc::apps::eval::evaluateLoopRecall(builder.graph(), kfs);
	std::printf("  %s", lrgc::apps::eval::calibrationReport(recall).c_str());
}

void printFigures(const char* what, const TScanOutliers& o)
{
	std::printf(
		"  %s: rmse %.4f m, worst %.3f m (scan %zu, %.1f x rmse), worst above its "
		"neighbours %.3f m (scan %zu)\n",
		what, o.rmse, o.worst, o.worstIndex, o.worst / o.rmse, o.worstAboveNeighbours,
		o.isolatedIndex);
}

TEST(CrowdedHall, everyScanFollowsTheMap)
{
	for (const uint32_t seed : hallSeeds())
	{
		const CSyntheticWorld world = makeOpenHallWorld(seed, 70, 45, 6);
		const TTrajectory tr = hallLoops(40 + seed);
		double clearance = INFINITY;
		for (const TPose2D& p : tr.truePoses)
			clearance = std::min(clearance, world.distanceToNearest({p.x, p.y}));
		ASSERT_GT(clearance, 0.5)
			<< "the hall's path runs into an obstacle (seed " << seed << ")";
		TSyntheticRunOptions opt;
		opt.laser.beams = 181;
		opt.laser.maxRange = 80;
		opt.laser.rangeNoiseStd = 0.015;
		opt.laser.dropRate = 0.05;
		opt.laser.outlierRate = 0.01;
		opt.laserSeed = seed;
		const CCrowd crowd({{2, 1}, {68, 44}}, 25, 200 + seed);
		opt.crowd = &crowd;
		CMetricMapBuilderLRGC builder;
		feedBuilder(builder, world, tr, opt);
		const auto err = alignedErrors(builder.trajectory(), tr.truePoses);
		const size_t lapEnd = firstPoseAt(tr.truePoses, 6, 6);
		ASSERT_LT(lapEnd, err.size());
		const TScanOutliers all = scanOutliers(err, 0, err.size());
		const TScanOutliers lap[2] = {scanOutliers(err, 0, lapEnd),
									  scanOutliers(err, lapEnd, err.size())};
		const double start = *std::max_element(err.begin(), err.begin() + 40);
		std::printf(
			"[ crowded hall ] seed %u: %zu scans, %zu loop closures, %zu settled, %zu patch "
			"links widened, first 10 m of the first lap within %.3f m\n",
			seed, err.size(), builder.stats().loopClosures, builder.stats().scansSettled,
			builder.stats().patchLinksWidened, start);
		printLoopCalibration(builder, tr.truePoses, opt.scanPeriod);
		printFigures("all", all);
		printFigures("lap 1", lap[0]);
		printFigures("lap 2", lap[1]);
		std::printf("  row: | %u | %.4f / %.3f (%.1fx) | %.4f / %.3f (%.1fx) | %.3f |\n", seed,
					lap[0].rmse, lap[0].worst, lap[0].worst / lap[0].rmse, lap[1].rmse,
					lap[1].worst, lap[1].worst / lap[1].rmse, start);
		// Issue 28's bars for such a hall: rmse <= 0.030 m, worst scan <= 0.25 m, and per lap
		// the worst scan within 3x the lap's rmse. Before the wide search's second opinion and
		// settleIsolatedScans: seed 1 rmse 0.032, worst 0.463 m (scan 1478, 0.444 above its
		// neighbours); seed 2 rmse 1.59 m, worst 10.3 m (a 23 deg wrong match at scan 1387).
		// Before the revisit radius of 2 m and smoothScans: seed 1 0.025 / 0.110 m (0.095
		// above its neighbours, lap 1 3.8x its rmse), seed 2 0.029 / 0.212 m (0.191 above,
		// lap 2 10.2x), its first 10 m within 0.093 m. Then 0.025 / 0.109 (lap 1 3.8x) and
		// 0.021 / 0.071 (lap 1 3.0x); with the smoothing's odometry weights taken anew at each
		// step, 0.025 / 0.109 (lap 1 3.9x) and 0.021 / 0.070 (lap 1 3.0x), the worst above its
		// neighbours 0.042 and 0.020 m. What is left is the leg along the glass facade after
		// the corner at (64, 39): no scan-to-scan match there, each keyframe on its patch link
		// alone, 5-6 cm sideways on both laps. Not the matcher's bias (the test below): the
		// heading carried across that corner, where the turn's last scans share only far
		// walls with the window and settle in a heading optimum 0.9 deg off
		// (doc/generalisation.md, CrowdedHall). With such patch links' position covariance
		// widened by the scan's sparseness (LocalRegistration.cpp, lonePatchLinkCov):
		// 0.020 / 0.060 m (lap 1 2.5x, lap 2 2.9x) and 0.021 / 0.064 m (lap 1 3.0x, lap 2
		// 2.0x). Lap 2's west leg (x = 5) runs through the pillars at (5, 33.75) and
		// (5, 11.25): the runs settleIsolatedScans settled were the scans taken inside them.
		// With that leg at x = 4 (task `crowd4`) none is settled, and the worst laps were the
		// scans between the keyframes after the corner at (64, 38), matched 5-10 cm sideways
		// where the keyframes' own matches failed (trajectory seed 44: scan 1137, 0.070 m, 4.3x
		// its lap's rmse); with their registration's covariance widened as a lone patch
		// match's for the smoothing (lonePatchLinkCov): 0.038 m, 2.4x. Seeds 1 and 2 now:
		// 0.018 / 0.057 m (lap 1 2.6x, lap 2 2.2x, the worst above its neighbours 0.012 m)
		// and 0.021 / 0.062 m (2.9x, 2.1x, 0.014 m).
		EXPECT_LT(all.rmse, 0.025);
		EXPECT_LT(all.worst, 0.08);  // before the widening: 0.109 m (seed 1)
		// Most keyframes here see only far walls (about 390 of 720 widened).
		EXPECT_GT(builder.stats().patchLinksWidened, builder.stats().keyframes / 4);
		for (const TScanOutliers& l : lap)
		{
			EXPECT_LT(l.worstAboveNeighbours, 0.03);  // before task `crowd4`: 0.08
			// Issue 28 asks for 3x: met on seeds 1 and 2 (2.4x at most) and on 15 of the 16
			// laps of seeds 1-8 (3.08x at most; doc/generalisation.md); before task `crowd4`:
			// 4x, before session 65's region_retry 14 of 16 (3.88x).
			EXPECT_LT(l.worst, 3.5 * l.rmse);
		}
		EXPECT_LT(start, 0.05);  // seeds 1-8: 0.015-0.045 m (before task `crowd4`: 0.08)
	}
}

/* The leg along the glass facade (y = 39, heading west, after the corner at (64, 39)) is where
 * the map is worst. This separates the scan matcher from the chain that feeds it: each scan
 * of the leg (x 8-62 m, every other step) is matched against the patch of the 15 keyframes
 * before it (every other step, 0.5 m apart, as the builder's K-window) built at their TRUE
 * poses, from a guess 3 cm and 0.5 deg off. Measured (seed 1, people walking): 109 of 109
 * matched, lateral error mean +0.9 mm, rms 4.5 mm, the covariance's lateral std 4.3 mm on
 * average. So the matcher, its voxels, line fits and robust weights are neither biased nor
 * over-confident here; the 2-10 cm sideways errors of the full run's patch links come from
 * the window's own poses (doc/generalisation.md, CrowdedHall). */
TEST(CrowdedHall, patchMatchAlongTheFacadeIsUnbiasedOnTruePoses)
{
	const uint32_t seed = 1;
	const CSyntheticWorld world = makeOpenHallWorld(seed, 70, 45, 6);
	const TTrajectory tr = hallLoops(40 + seed);
	TLaserSimParams laser;
	laser.beams = 181;
	laser.maxRange = 80;
	laser.rangeNoiseStd = 0.015;
	laser.dropRate = 0.05;
	laser.outlierRate = 0.01;
	const CCrowd crowd({{2, 1}, {68, 44}}, 25, 200 + seed);
	std::mt19937 rng(seed);
	auto scanAt = [&](size_t k)
	{
		const TPose2D& p = tr.truePoses[k];
		return simulateScan(crowd.addTo(world, 0.2 * double(k), {p.x, p.y}), p, laser, rng);
	};
	lrgc::TScanMatcherParams mp;
	mp.max_free_space_violation = 0.3;  // local registration's ([LocalRegistration])
	const lrgc::CScanMatcher matcher(mp);
	constexpr size_t kStride = 2, kWindow = 15;
	double sumLat = 0, sumLat2 = 0, sumStd = 0;
	size_t n = 0, tried = 0;
	for (size_t k = kStride * kWindow; k < tr.truePoses.size(); k += kStride)
	{
		const TPose2D& p = tr.truePoses[k];
		if (std::abs(p.y - 39) > 1e-6 || std::abs(std::abs(p.phi) - M_PI) > 1e-3 || p.x < 8 ||
			p.x > 62)
			continue;
		++tried;
		std::vector<lrgc::TScan2D> scans;
		std::vector<TPose2D> inNewest;
		const TPose2D& newest = tr.truePoses[k - kStride];
		for (size_t j = kWindow; j >= 1; --j)
		{
			scans.push_back(scanAt(k - kStride * j));
			inNewest.push_back(lrgc::between(newest, tr.truePoses[k - kStride * j]));
		}
		const auto patch = lrgc::CReferenceCloud::fromScans(scans, inNewest, mp);
		const TPose2D truth = lrgc::between(newest, p);
		const TPose2D guess =
			lrgc::compose(truth, TPose2D(0.03, 0.03, mrpt::DEG2RAD(0.5)));  // robot frame
		const auto m = matcher.match(patch, scanAt(k), guess);
		if (!m) continue;
		const double lateral = lrgc::between(truth, m->scanInRef).y;  // [m], robot frame
		// The covariance is in the patch's (newest keyframe's) frame: its lateral axis is the
		// robot's y rotated by truth.phi.
		const Eigen::Vector2d y(-std::sin(truth.phi), std::cos(truth.phi));
		sumLat += lateral, sumLat2 += lateral * lateral;
		sumStd += std::sqrt(y.dot(m->cov.topLeftCorner<2, 2>() * y));
		++n;
	}
	ASSERT_GT(tried, 100u);
	const double mean = sumLat / double(n), rms = std::sqrt(sumLat2 / double(n)),
				 claimed = sumStd / double(n);
	std::printf(
		"[ crowded hall ] facade leg on true poses: %zu of %zu matched, lateral error mean "
		"%+.4f m, rms %.4f m, the covariance's lateral std %.4f m on average\n",
		n, tried, mean, rms, claimed);
	EXPECT_GE(n, tried * 95 / 100);
	EXPECT_LT(std::abs(mean), 0.003);  // a 2 cm bias, as the full run's links, would fail
	EXPECT_LT(rms, 0.01);
	EXPECT_GT(claimed, 0.5 * rms);  // honest: not over-confident
}
