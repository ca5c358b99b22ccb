/* CScanMatcher on the synthetic world: accuracy, covariance consistency (NEES), corridors,
 * outliers, partial overlap, gaps, honest rejection. Every trial is seeded. The wide search:
 * ScanMatcher_wide_unittest.cpp. */
#include <gtest/gtest.h>
#include <lrgc/scan_matching/ScanMatcher.h>
#include <lrgc/common/se2.h>

#include <Eigen/Dense>
#include <cmath>
#include <iostream>

#include "ScanMatcherDetail.h"
#include "ScanMatcher_unittest.h"
#include "synthetic_world.h"

using namespace lrgc;
using namespace lrgc::test;
using mrpt::math::TPose2D;

namespace
{
struct TTrialStats
{
	int trials = 0, matched = 0;
	double sumNees = 0, sumNeesX = 0;
	std::vector<double> neesList;
	std::vector<std::pair<Eigen::Vector3d, Eigen::Matrix3d>> errCov;
	double neesScaled(double k) const
	{
		double sum = 0;
		for (const auto& [e, C] : errCov) sum += e.dot((k * C).inverse() * e);
		return sum / std::max<size_t>(1, errCov.size());
	}
	std::vector<double> transErr, rotErr;
	double median(std::vector<double> v) const
	{
		if (v.empty()) return NAN;
		std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
		return v[v.size() / 2];
	}
	double quantile(std::vector<double> v, double q) const
	{
		if (v.empty()) return NAN;
		std::sort(v.begin(), v.end());
		return v[std::min(v.size() - 1, static_cast<size_t>(q * v.size()))];
	}
	double nees() const { return sumNees / std::max(1, matched); }
	void print(const char* name) const
	{
		std::cout << name << ": matched " << matched << "/" << trials << ", NEES " << nees()
				  << ", trans err median " << median(transErr) * 1000 << " mm (95% "
				  << quantile(transErr, 0.95) * 1000 << "), rot err median "
				  << median(rotErr) / kDeg << " deg (95% " << quantile(rotErr, 0.95) / kDeg
				  << ")"
				  << " NEES median " << median(neesList) << " q90 " << quantile(neesList, 0.9)
				  << " q99 " << quantile(neesList, 0.99) << "\n";
	}
};

void record(TTrialStats& st, const std::optional<TScanMatch>& m, const TPose2D& truth,
			double covScale = 1)
{
	++st.trials;
	if (!m) return;
	++st.matched;
	const Eigen::Vector3d e = poseError(m->scanInRef, truth);
	st.sumNees += e.dot((covScale * m->cov).inverse() * e);
	st.neesList.push_back(e.dot((covScale * m->cov).inverse() * e));
	st.errCov.emplace_back(e, m->cov);
	if (std::getenv("LRGC_DEBUG_TRIALS") && e.head<2>().norm() > 0.02)
		std::cout << "  trial " << st.trials << " err " << e.transpose() << " sd "
				  << m->cov.diagonal().cwiseSqrt().transpose() << " inliers "
				  << m->inlierFraction << " free-space violation " << m->freeSpaceViolation
				  << " unobs " << m->unobservableDims << "\n";

	if (m->unobservableDims > 0) return;  // accuracy is for fully constrained matches
	st.transErr.push_back(e.head<2>().norm());
	st.rotErr.push_back(std::abs(e.z()));
}

/** Scan-to-scan trials in room worlds; covScale multiplies the reported covariance. */
TTrialStats roomTrials(int n, uint32_t seed, const TLaserSimParams& laser, double covScale = 1,
					   const TScanMatcherParams& params = {})
{
	TTrialStats st;
	std::mt19937 rng(seed);
	const CScanMatcher matcher(params);
	for (int t = 0; t < n; ++t)
	{
		const auto world = makeRoomWorld(seed + t);
		const auto [a, b] = roomPosePair(world, rng, 0.3, 10 * kDeg);
		const auto scanA = simulateScan(world, a, laser, rng);
		const auto scanB = simulateScan(world, b, laser, rng);
		const TPose2D truth = between(a, b);
		const auto ref = CReferenceCloud::fromScan(scanA, params);
		record(st, matcher.match(ref, scanB, perturb(truth, 0.05, 2 * kDeg, rng)), truth,
			   covScale);
	}
	return st;
}
}  // namespace

// NEES bound: the mean of e^T C^-1 e over N trials is chi2(3)/N-distributed for a consistent
// covariance: 3 +- 0.14 (1 sigma) at N = 300. We accept [1.8, 3.8]: a little conservatism is
// allowed (the paper: never over-confident); over-confidence by 30% in variance fails.
constexpr double kNeesLow = 1.8, kNeesHigh = 3.8;

TEST(ScanMatcher, roomScanToScanIsAccurateAndConsistent)
{
	TLaserSimParams laser;  // 361 beams, 1 cm noise
	const auto st = roomTrials(300, 1000, laser);
	st.print("room 361 beams");
	EXPECT_GE(st.matched, 290);
	EXPECT_LT(st.median(st.transErr), 0.003);
	EXPECT_LT(st.quantile(st.transErr, 0.95), 0.008);
	EXPECT_LT(st.median(st.rotErr), 0.05 * kDeg);
	EXPECT_GT(st.nees(), kNeesLow);
	EXPECT_LT(st.nees(), kNeesHigh);
	// The bound has teeth: the same trials with the covariance scaled by 0.3 fail it.
	EXPECT_GT(st.neesScaled(0.3), kNeesHigh);
}

TEST(ScanMatcher, roomScanToScan180BeamsAndNoisierLaser)
{
	TLaserSimParams laser;
	laser.beams = 180;
	const auto st = roomTrials(300, 2000, laser);
	st.print("room 180 beams");
	EXPECT_GE(st.matched, 285);
	EXPECT_LT(st.median(st.transErr), 0.004);
	EXPECT_GT(st.nees(), kNeesLow);
	EXPECT_LT(st.nees(), kNeesHigh);

	laser.beams = 361;
	laser.rangeNoiseStd = 0.03;  // a cheap laser
	const auto st3 = roomTrials(300, 3000, laser);
	st3.print("room 361 beams, 3 cm noise");
	EXPECT_GE(st3.matched, 280);
	EXPECT_GT(st3.nees(), kNeesLow);
	EXPECT_LT(st3.nees(), kNeesHigh);
}

TEST(ScanMatcher, scanToPatchOfTenScans)
{
	// A robot drives through the room; a patch of 10 scans at their true poses (ref = world)
	// is matched by the 11th scan from a dead-reckoned guess.
	TTrialStats st;
	std::mt19937 rng(77);
	const TScanMatcherParams params;
	const CScanMatcher matcher(params);
	TLaserSimParams laser;
	for (int t = 0; t < 200; ++t)
	{
		const auto world = makeRoomWorld(500 + t);
		std::vector<Eigen::Vector2d> wp;
		for (int k = 0; k < 4; ++k)
			for (;;)
				if (const auto p = sampleFreePose(world, {{1.5, 1.5}, {8.5, 5.5}}, 0.6, rng))
				{
					wp.emplace_back(p->x, p->y);
					break;
				}
		const auto traj = makeTrajectory(wp, 0.15, TOdometryNoise{}, 900 + t);
		if (traj.truePoses.size() < 11) continue;
		std::vector<TScan2D> scans;
		std::vector<TPose2D> poses(traj.truePoses.begin(), traj.truePoses.begin() + 10);
		for (const auto& p : poses) scans.push_back(simulateScan(world, p, laser, rng));
		const auto ref = CReferenceCloud::fromScans(scans, poses, params);
		const TPose2D truth = traj.truePoses[10];
		const TPose2D guess = compose(poses[9], traj.odometryIncrements[9]);
		record(st, matcher.match(ref, simulateScan(world, truth, laser, rng), guess), truth);
	}
	st.print("scan to 10-scan patch");
	EXPECT_GE(st.matched, 0.97 * st.trials);
	EXPECT_LT(st.median(st.transErr), 0.002);
	EXPECT_GT(st.nees(), kNeesLow);
	EXPECT_LT(st.nees(), kNeesHigh);
}

TEST(ScanMatcher, corridorAxisIsReportedUnobservable)
{
	const auto world = makeCorridorWorld(200, 2.0);
	std::mt19937 rng(8);
	std::normal_distribution<double> N(0, 1);
	TLaserSimParams laser;
	const TScanMatcherParams params;
	const CScanMatcher matcher(params);
	double sumNeesAlong = 0, sumNeesAcross = 0;
	int matched = 0, flagged = 0, wide = 0;
	const int trials = 200;
	for (int t = 0; t < trials; ++t)
	{
		const TPose2D a(100 + 10 * N(rng), 1 + 0.2 * N(rng), 0.1 * N(rng));
		const TPose2D b =
			compose(a, TPose2D(0.3 + 0.05 * N(rng), 0.05 * N(rng), 0.03 * N(rng)));
		const auto ref = CReferenceCloud::fromScan(simulateScan(world, a, laser, rng), params);
		const TPose2D truth = between(a, b);
		const TPose2D guess =
			compose(truth, TPose2D(0.2 * N(rng), 0.03 * N(rng), 0.02 * N(rng)));
		const auto m = matcher.match(ref, simulateScan(world, b, laser, rng), guess);
		if (!m) continue;
		++matched;
		flagged += m->unobservableDims == 1;
		// Axis and normal of the corridor in the ref frame (the corridor runs along world x).
		const Eigen::Vector2d along(std::cos(-a.phi), std::sin(-a.phi)),
			across(-along.y(), along.x());
		const Eigen::Matrix2d Cxy = m->cov.topLeftCorner<2, 2>();
		const double varAlong = along.dot(Cxy * along), varAcross = across.dot(Cxy * across);
		wide += varAlong > 1e3 * varAcross;
		const Eigen::Vector3d e = poseError(m->scanInRef, truth);
		sumNeesAlong += std::pow(along.dot(e.head<2>()), 2) / varAlong;
		sumNeesAcross += std::pow(across.dot(e.head<2>()), 2) / varAcross;
	}
	std::cout << "corridor: matched " << matched << "/" << trials << ", NEES along "
			  << sumNeesAlong / matched << ", across " << sumNeesAcross / matched << "\n";
	EXPECT_GE(matched, 0.95 * trials);
	EXPECT_EQ(flagged, matched);
	EXPECT_EQ(wide, matched);
	EXPECT_LT(sumNeesAlong / matched, 1.0);  // chi2(1) mean is 1: never over-confident
	EXPECT_LT(sumNeesAcross / matched, 1.5);
}

TEST(ScanMatcher, robustToOutliersPartialOverlapAndGaps)
{
	std::mt19937 rng(31);
	const TScanMatcherParams params;
	const CScanMatcher matcher(params);
	TTrialStats out, half, gap;
	for (int t = 0; t < 200; ++t)
	{
		const auto world = makeRoomWorld(700 + t);
		const auto [a, b] = roomPosePair(world, rng, 0.3, 10 * kDeg);
		const TPose2D truth = between(a, b);
		const TPose2D guess = perturb(truth, 0.05, 2 * kDeg, rng);
		TLaserSimParams noisy;
		noisy.outlierRate = 0.15;  // 15% spurious returns in both scans
		{
			const auto ref =
				CReferenceCloud::fromScan(simulateScan(world, a, noisy, rng), params);
			record(out, matcher.match(ref, simulateScan(world, b, noisy, rng), guess), truth);
		}
		TLaserSimParams laser;
		TScan2D scanA = simulateScan(world, a, laser, rng);
		TScan2D scanB = simulateScan(world, b, laser, rng);
		{
			TScan2D leftHalf = scanA;  // the ref keeps only its right half: ~50% overlap
			removeBearingSector(leftHalf, 0, M_PI);
			record(half,
				   matcher.match(CReferenceCloud::fromScan(leftHalf, params), scanB, guess),
				   truth);
		}
		removeBearingSector(scanB, -35 * kDeg, 35 * kDeg);  // a 70 deg run of no-returns
		record(gap, matcher.match(CReferenceCloud::fromScan(scanA, params), scanB, guess),
			   truth);
	}
	out.print("15% outliers");
	half.print("50% overlap");
	gap.print("70 deg gap");
	for (const TTrialStats* st : {&out, &half, &gap})
	{
		EXPECT_GE(st->matched, 0.9 * st->trials);
		EXPECT_LT(st->median(st->transErr), 0.004);
		EXPECT_LT(st->quantile(st->transErr, 0.95), 0.02);
		EXPECT_LT(st->nees(), 1.5 * kNeesHigh);
	}
}

TEST(ScanMatcher, saysNoMatchInsteadOfReturningTheGuess)
{
	std::mt19937 rng(41);
	const TScanMatcherParams params;
	const CScanMatcher matcher(params);
	TLaserSimParams laser;
	const auto room = makeRoomWorld(1);
	const auto corridor = makeCorridorWorld(200, 2.0);
	int noOverlapAccepted = 0, farAccepted = 0, farWrong = 0;
	const int trials = 100;
	for (int t = 0; t < trials; ++t)
	{
		const auto [a, b] = roomPosePair(room, rng, 0.3, 10 * kDeg);
		const auto ref = CReferenceCloud::fromScan(simulateScan(room, a, laser, rng), params);
		// A scan of another place altogether.
		const auto other = simulateScan(corridor, TPose2D(100, 1, 0.3), laser, rng);
		const auto wrongM = matcher.match(ref, other, TPose2D(0, 0, 0));
		noOverlapAccepted += wrongM.has_value();
		if (wrongM && std::getenv("LRGC_DEBUG_TRIALS"))
			std::cout << "  no-overlap accepted: inliers " << wrongM->inlierFraction << " free "
					  << wrongM->freeSpaceViolation << " unobs " << wrongM->unobservableDims
					  << " rms " << wrongM->rmsResidual << "\n";
		// The right scan, but a guess 1.5-3 m and 20-40 deg away from the truth.
		std::uniform_real_distribution<double> ud(1.5, 3), ua(20 * kDeg, 40 * kDeg),
			us(-M_PI, M_PI);
		const double d = ud(rng), dir = us(rng), dphi = (t % 2 ? 1 : -1) * ua(rng);
		const TPose2D truth = between(a, b);
		const TPose2D guess(truth.x + d * std::cos(dir), truth.y + d * std::sin(dir),
							truth.phi + dphi);
		const auto m = matcher.match(ref, simulateScan(room, b, laser, rng), guess);
		if (!m) continue;
		++farAccepted;
		const Eigen::Vector3d e = poseError(m->scanInRef, truth);
		farWrong += e.dot(m->cov.inverse() * e) > 16.27;  // chi2(3) at 99.9%
		if (std::getenv("LRGC_DEBUG_TRIALS"))
			std::cout << "  far accepted: err " << e.transpose() << " nees "
					  << e.dot(m->cov.inverse() * e) << " inliers " << m->inlierFraction
					  << " free " << m->freeSpaceViolation << "\n";
	}
	std::cout << "no overlap accepted " << noOverlapAccepted << "/" << trials
			  << ", far guess accepted " << farAccepted << " (wrong " << farWrong << ")\n";
	EXPECT_EQ(noOverlapAccepted, 0);
	EXPECT_LE(farWrong, 2);
	EXPECT_LE(farAccepted, trials / 2);  // mostly an honest "no"
	// Empty inputs.
	EXPECT_FALSE(
		matcher.match(CReferenceCloud(), simulateScan(room, TPose2D(5, 3, 0), laser, rng), {}));
	EXPECT_FALSE(matcher.match(
		CReferenceCloud::fromScan(simulateScan(room, TPose2D(5, 3, 0), laser, rng), params),
		TScan2D{}, {}));
}

// CScanMatcher::refitLoose: a loose fit (residual scale that kept the gate at its start) of a
// scan that shares an L corner with the reference and sees new ground besides is refitted
// onto the corner; a fit that is not loose, or whose refit explains no more, is kept.
TEST(ScanMatcher, refitLooseMovesACompromiseOntoTheSharedWalls)
{
	const TScanMatcherParams params;
	const CScanMatcher matcher(params);
	auto wall = [](std::vector<Eigen::Vector2d>& out, Eigen::Vector2d a, Eigen::Vector2d b)
	{
		const int n = static_cast<int>((b - a).norm() / 0.02);
		for (int i = 0; i <= n; ++i) out.push_back(a + (b - a) * (double(i) / n));
	};
	std::vector<Eigen::Vector2d> refPts;
	wall(refPts, {0, 0}, {4, 0});
	wall(refPts, {4, 0}, {4, 3});
	const CReferenceCloud ref(refPts, params);
	TScan2D scan;  // at the reference's origin: the corner, and a wall the reference lacks
	wall(scan.points, {2, 0}, {4, 0});
	wall(scan.points, {4, 0}, {4, 3});
	wall(scan.points, {1, 1.5}, {1, 4});
	// A compromise 3 deg and 0.28 m off, loose: s = 0.06 m keeps the 0.5 m gate open.
	TScanMatch loose;
	loose.scanInRef = TPose2D(0.2, -0.2, 3 * kDeg);
	loose.residualStd = 0.06;
	const TScanMatch refit = matcher.refitLoose(ref, scan, loose);
	EXPECT_LT(poseError(refit.scanInRef, TPose2D(0, 0, 0)).head<2>().norm(), 0.005);
	EXPECT_LT(std::abs(refit.scanInRef.phi), 0.1 * kDeg);
	EXPECT_GT(matcher.explainedFraction(ref, scan, refit.scanInRef),
			  matcher.explainedFraction(ref, scan, loose.scanInRef) + 0.05);
	// Not loose (4 * 2.385 * 0.03 m < 0.5 m): kept as it is.
	TScanMatch tight = loose;
	tight.residualStd = 0.03;
	EXPECT_EQ(poseError(matcher.refitLoose(ref, scan, tight).scanInRef, tight.scanInRef).norm(),
			  0.0);
	// Loose, but already where the refit lands (it explains no more): kept.
	TScanMatch right = loose;
	right.scanInRef = TPose2D(0, 0, 0);
	EXPECT_EQ(poseError(matcher.refitLoose(ref, scan, right).scanInRef, right.scanInRef).norm(),
			  0.0);
}

// A denoised scan (TScan2D::matchStride 4) is matched on every fourth point: the same pose,
// iterations and inlier share, bit for bit, as the scan cut to those points, and not those of
// the whole scan. (Stop 50, doc/architecture.md: on main every point was matched.)
TEST(ScanMatcher, aDenoisedScanIsMatchedOnEveryMatchStrideThPoint)
{
	std::mt19937 rng(31);
	const TScanMatcherParams params;
	const CScanMatcher matcher(params);
	const auto world = makeRoomWorld(31);
	const auto [a, b] = roomPosePair(world, rng, 0.3, 10 * kDeg);
	const auto ref =
		CReferenceCloud::fromScan(simulateScan(world, a, TLaserSimParams{}, rng), params);
	TScan2D scan = simulateScan(world, b, TLaserSimParams{}, rng);
	ASSERT_GE(scan.points.size(), 8u * params.min_inliers);  // so the stride is not shrunk
	const TPose2D guess = perturb(between(a, b), 0.05, 2 * kDeg, rng);
	TScan2D cut = scan;  // the same range image: the free-space check's other half
	cut.points.clear();
	for (size_t i = 0; i < scan.points.size(); i += 4) cut.points.push_back(scan.points[i]);
	const auto whole = matcher.match(ref, scan, guess);
	scan.matchStride = 4;
	const auto strided = matcher.match(ref, scan, guess);
	const auto ofCut = matcher.match(ref, cut, guess);
	ASSERT_TRUE(whole && strided && ofCut);
	EXPECT_EQ(strided->scanInRef.x, ofCut->scanInRef.x);
	EXPECT_EQ(strided->scanInRef.y, ofCut->scanInRef.y);
	EXPECT_EQ(strided->scanInRef.phi, ofCut->scanInRef.phi);
	EXPECT_EQ(strided->iterations, ofCut->iterations);
	EXPECT_EQ(strided->inlierFraction, ofCut->inlierFraction);
	EXPECT_NE(strided->scanInRef.x, whole->scanInRef.x);
	EXPECT_LT(translationNorm(between(strided->scanInRef, between(a, b))), 0.01);
}

// The bread term of a POINT residual (cauchyPointBread, the closed form of its eigenvalues
// floored at 0): e / |e| and the direction across it are its eigenvectors, with eigenvalues
// max(0, w (1 - 2 w |e|^2 / c^2)) and w. Along e that is (c^2 - |e|^2) / (c^2 + |e|^2) w:
// the plain derivative up to |e| = c, 0 beyond. Residuals of 0.1-3 c at several bearings.
TEST(ScanMatcherCovariance, aPointResidualsBreadIsTheCauchyDerivativeFlooredAtZero)
{
	const double c = 0.1, c2 = c * c;
	for (const double r : {0.01, 0.05, 0.099, 0.1, 0.101, 0.3})
		for (const double bearing : {0.0, 0.4, 1.9, -2.7})
		{
			const Eigen::Vector2d u(std::cos(bearing), std::sin(bearing)),
				across(-u.y(), u.x());
			const Eigen::Vector2d e = r * u;
			const double w = 1 / (1 + r * r / c2);
			const Eigen::Matrix2d D = detail::cauchyPointBread(w, e, c2);
			const double along = std::max(0.0, w * (1 - 2 * w * r * r / c2));
			EXPECT_NEAR((D * u - along * u).norm(), 0, 1e-12) << "|e| " << r;
			EXPECT_NEAR((D * across - w * across).norm(), 0, 1e-12) << "|e| " << r;
			EXPECT_NEAR(D(0, 1), D(1, 0), 1e-15);
		}
}
