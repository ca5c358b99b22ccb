/* CScanMatcher on the synthetic world: accuracy, covariance consistency (NEES), corridors,
 * outliers, partial overlap, gaps, honest rejection, wide search. Every trial is seeded. */
#include <gtest/gtest.h>
#include <lrgc/ScanMatcher.h>
#include <lrgc/se2.h>

#include <Eigen/Dense>
#include <cmath>
#include <iostream>

#include "synthetic_world.h"

using namespace lrgc;
using namespace lrgc::test;
using mrpt::math::TPose2D;

namespace
{
constexpr double kDeg = M_PI / 180;

struct TTrialStats
{
	int trials = 0, matched = 0;
	double sumNees = 0, sumNeesX = 0;
	std::vector<double> neesList;
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
				  << quantile(transErr, 0.95) * 1000 << "), rot err median " << median(rotErr) / kDeg
				  << " deg (95% " << quantile(rotErr, 0.95) / kDeg << ")"
				  << " NEES median " << median(neesList) << " q90 " << quantile(neesList, 0.9)
				  << " q99 " << quantile(neesList, 0.99) << "\n";
	}
};

Eigen::Vector3d poseError(const TPose2D& est, const TPose2D& truth)
{
	return {est.x - truth.x, est.y - truth.y, mrpt::math::wrapToPi(est.phi - truth.phi)};
}

void record(TTrialStats& st, const std::optional<TScanMatch>& m, const TPose2D& truth, double covScale = 1)
{
	++st.trials;
	if (!m) return;
	++st.matched;
	const Eigen::Vector3d e = poseError(m->scanInRef, truth);
	st.sumNees += e.dot((covScale * m->cov).inverse() * e);
	st.neesList.push_back(e.dot((covScale * m->cov).inverse() * e));
	if (std::getenv("DEBUG_NEES") && st.neesList.back() > 15)
		std::cout << "trial " << st.trials << " nees " << st.neesList.back() << " e " << e.transpose()
				  << " sd " << m->cov.diagonal().cwiseSqrt().transpose() << " inl " << m->inlierFraction
				  << " s " << m->residualStd << " it " << m->iterations << "\n";
	st.transErr.push_back(e.head<2>().norm());
	st.rotErr.push_back(std::abs(e.z()));
}

TPose2D perturb(const TPose2D& p, double sdXY, double sdPhi, std::mt19937& rng)
{
	std::normal_distribution<double> N(0, 1);
	return {p.x + sdXY * N(rng), p.y + sdXY * N(rng), mrpt::math::wrapToPi(p.phi + sdPhi * N(rng))};
}

/** A pair of poses in a room world: A free, B = A (+) a random motion, also free. */
std::pair<TPose2D, TPose2D> roomPosePair(const CSyntheticWorld& w, std::mt19937& rng, double dist, double turn)
{
	const TBox region{{1, 1}, {9, 6}};
	for (;;)
	{
		const auto a = sampleFreePose(w, region, 0.5, rng);
		if (!a) continue;
		std::uniform_real_distribution<double> u(-1, 1);
		const TPose2D b = compose(*a, TPose2D(dist * u(rng), dist * u(rng), turn * u(rng)));
		if (w.distanceToNearest({b.x, b.y}) > 0.4 && b.x > 0.3 && b.x < 9.7 && b.y > 0.3 && b.y < 6.7)
			return {*a, b};
	}
}

/** Scan-to-scan trials in room worlds; covScale multiplies the reported covariance. */
TTrialStats roomTrials(
	int n, uint32_t seed, const TLaserSimParams& laser, double covScale = 1,
	const TScanMatcherParams& params0 = {})
{
	TTrialStats st;
	std::mt19937 rng(seed);
	TScanMatcherParams params = params0;
	if (std::getenv("NR")) params.normalRadius_m = std::atof(std::getenv("NR"));
	if (std::getenv("RES")) params.refResolution_m = std::atof(std::getenv("RES"));
	const int clutter = std::getenv("CLUTTER") ? std::atoi(std::getenv("CLUTTER")) : 8;
	const CScanMatcher matcher(params);
	for (int t = 0; t < n; ++t)
	{
		const auto world = makeRoomWorld(seed + t, clutter);
		const auto [a, b] = roomPosePair(world, rng, 0.3, 10 * kDeg);
		TLaserSimParams laserA = laser;
		if (std::getenv("REF_NOISE")) laserA.rangeNoiseStd = std::atof(std::getenv("REF_NOISE"));
		const auto scanA = simulateScan(world, a, laserA, rng);
		const auto scanB = simulateScan(world, b, laser, rng);
		const TPose2D truth = between(a, b);
		const auto ref = CReferenceCloud::fromScan(scanA, params);
		record(st, matcher.match(ref, scanB, perturb(truth, 0.05, 2 * kDeg, rng)), truth, covScale);
	}
	return st;
}
}  // namespace

TEST(ScanMatcher, roomScanToScanIsAccurateAndConsistent)
{
	TLaserSimParams laser;  // 361 beams, 1 cm noise
	if (std::getenv("SCAN_NOISE")) laser.rangeNoiseStd = std::atof(std::getenv("SCAN_NOISE"));
	const auto st = roomTrials(300, 1000, laser);
	st.print("room 361 beams");
	EXPECT_GE(st.matched, 290);
	EXPECT_LT(st.median(st.transErr), 0.003);
	EXPECT_LT(st.median(st.rotErr), 0.1 * kDeg);
	EXPECT_NEAR(st.nees(), 3.0, 1.0);
}

TEST(ScanMatcher, roomScanToScan180Beams)
{
	TLaserSimParams laser;
	laser.beams = 180;
	const auto st = roomTrials(300, 2000, laser);
	st.print("room 180 beams");
	EXPECT_GE(st.matched, 290);
	EXPECT_NEAR(st.nees(), 3.0, 1.0);
}
