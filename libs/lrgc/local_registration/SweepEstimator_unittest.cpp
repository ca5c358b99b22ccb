/* CSweepEstimator (online sweep time for de-skewing) on a synthetic room: a robot turning in
 * place back and forth, its laser sweeping its 361 beams over a known time while it turns.
 * The estimator recovers that time; without turns it estimates nothing; a fixed
 * [MapBuilder] scan_sweep_time_s overrides it. fitSkew recovers a known skew. */
#include <gtest/gtest.h>
#include <lrgc/local_registration/SweepEstimator.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace lrgc;
using mrpt::math::TPose2D;

namespace
{
constexpr double kRoomHalfX = 4.0,
				 kRoomHalfY = 3.0;          // [m] rectangular room, centred at the origin
const Eigen::Vector2d kRobotAt(0.7, -0.4);  // [m] the robot turns in place here (off centre)
constexpr size_t kBeams = 361;

/** Range from kRobotAt along direction a [rad] (room frame) to the walls. */
double rangeFromRobot(double a)
{
	const double c = std::cos(a), s = std::sin(a);
	double r = 1e9;
	if (std::abs(c) > 1e-12)
		r = std::min(r, ((c > 0 ? kRoomHalfX : -kRoomHalfX) - kRobotAt.x()) / c);
	if (std::abs(s) > 1e-12)
		r = std::min(r, ((s > 0 ? kRoomHalfY : -kRoomHalfY) - kRobotAt.y()) / s);
	return r;
}

/** A 180 deg scan whose middle beam fires at heading heading(0); beam i at time
 * (i / 360 - 1/2) tau, when the heading is heading(t). Ranges with 5 mm noise. */
template <class Heading>
mrpt::obs::CObservation2DRangeScan scanWhileTurning(Heading heading, double tau,
													std::mt19937& rng)
{
	std::normal_distribution<double> noise(0.0, 0.005);
	mrpt::obs::CObservation2DRangeScan obs;
	obs.aperture = M_PI;
	obs.rightToLeft = true;
	obs.maxRange = 80;
	obs.resizeScan(kBeams);
	for (size_t i = 0; i < kBeams; ++i)
	{
		const double t = (double(i) / (kBeams - 1) - 0.5) * tau;
		const double beam = -M_PI / 2 + M_PI * double(i) / (kBeams - 1);
		obs.setScanRange(i, static_cast<float>(rangeFromRobot(beam + heading(t)) + noise(rng)));
		obs.setScanRangeValidity(i, true);
	}
	return obs;
}

/** Feeds `scans` scans, period T [s], of a robot whose heading is phi(t) [rad], with sweep
 * time tau [s]; each scan is de-skewed with the estimator's current sweep time by the
 * (odometry) step over its time, as CMetricMapBuilderLRGC does. */
template <class Phi>
void feed(CSweepEstimator& est, Phi phi, size_t scans, double T, double tau)
{
	std::mt19937 rng(7);
	for (size_t k = 0; k < scans; ++k)
	{
		const double tk = double(k) * T;
		const auto obs = scanWhileTurning([&](double t) { return phi(tk + t); }, tau, rng);
		const double step = k > 0 ? phi(tk) - phi(tk - T) : 0.0;
		const double rate = step / T;  // the predicted step over its time
		const double applied = std::min(1.0, est.sweepTime() / T) * step;
		const TScan2D scan = scanFromObservation(obs, nullptr, TPose2D(0, 0, applied));
		est.observe(obs, scan, rate, applied, TPose2D(0, 0, step), true);
	}
}

TSweepEstimatorParams on()
{
	TSweepEstimatorParams p;
	p.enabled = true;
	return p;
}

// Back and forth: rate 1.5 sin(2 pi t / 4) rad/s, heading within +-0.95 rad.
double swinging(double t)
{
	return -1.5 * 4 / (2 * M_PI) * std::cos(2 * M_PI * t / 4);
}
}  // namespace

TEST(SweepEstimator, fitSkewRecoversTheSkewOfATurningScan)
{
	std::mt19937 rng(3);
	const double w = 2.0, tau = 0.02;  // 40 mrad over the sweep
	const auto refObs = scanWhileTurning([](double) { return 0.0; }, tau, rng);
	const auto obs = scanWhileTurning([&](double t) { return 0.1 + w * t; }, tau, rng);
	const CReferenceCloud ref =
		CReferenceCloud::fromScan(scanFromObservation(refObs), TScanMatcherParams());
	const auto fit =
		fitSkew(ref, scanFromObservation(obs), sweepFractions(obs), TPose2D(0, 0, 0.08));
	ASSERT_TRUE(fit);
	EXPECT_NEAR(fit->skew, w * tau, 0.003);
	EXPECT_NEAR(fit->scanInRef.phi, 0.1, 0.002);
	EXPECT_NEAR(fit->scanInRef.x, 0.0, 0.005);
	// The same scan de-skewed has no skew left.
	const auto straight =
		fitSkew(ref, scanFromObservation(obs, nullptr, TPose2D(0, 0, w * tau)),
				sweepFractions(obs), TPose2D(0, 0, 0.08));
	ASSERT_TRUE(straight);
	EXPECT_NEAR(straight->skew, 0.0, 0.003);
}

TEST(SweepEstimator, recoversTheSweepTimeFromTurns)
{
	for (const double tau : {0.0067, 0.0267})
	{
		CSweepEstimator est(on(), TScanMatcherParams(), 0.0);
		EXPECT_EQ(est.sweepTime(), 0.0);  // nothing known yet: no de-skewing
		feed(est, swinging, 300, 0.1, tau);
		const TSweepEstimate& s = est.summary();
		EXPECT_TRUE(s.estimated) << "tau " << tau << ", std " << s.std << ", pairs "
								 << s.samples;
		EXPECT_GT(s.samples, 100u);
		EXPECT_NEAR(est.sweepTime(), tau, 0.15 * tau + 0.0005) << "std " << s.std;
	}
}

TEST(SweepEstimator, noTurnsNoEstimate)
{
	CSweepEstimator est(on(), TScanMatcherParams(), 0.0);
	feed(
		est, [](double) { return 0.3; }, 100, 0.1, 0.0267);
	EXPECT_EQ(est.summary().samples, 0u);
	EXPECT_FALSE(est.summary().estimated);
	EXPECT_EQ(est.sweepTime(), 0.0);
	// A steady turn stretches every scan alike: only the first scans (the first one, at
	// rest, is within the 10 recent ones) are compared, too few for an estimate.
	CSweepEstimator steady(on(), TScanMatcherParams(), 0.0);
	feed(
		steady, [](double t) { return 0.5 * t; }, 100, 0.1, 0.0267);
	EXPECT_LE(steady.summary().samples, 10u);
	EXPECT_FALSE(steady.summary().estimated);
	EXPECT_EQ(steady.sweepTime(), 0.0);
}

TEST(SweepEstimator, aFixedSweepTimeOrDisablingOverridesTheEstimate)
{
	CSweepEstimator fixed(on(), TScanMatcherParams(), 0.0045);
	feed(fixed, swinging, 100, 0.1, 0.0267);
	EXPECT_EQ(fixed.sweepTime(), 0.0045);
	EXPECT_EQ(fixed.summary().samples, 0u);
	TSweepEstimatorParams off;  // the default
	CSweepEstimator disabled(off, TScanMatcherParams(), 0.0);
	feed(disabled, swinging, 100, 0.1, 0.0267);
	EXPECT_EQ(disabled.sweepTime(), 0.0);
	EXPECT_EQ(disabled.summary().samples, 0u);
}

TEST(SweepEstimator, outliersDoNotMoveTheEstimate)
{
	TSweepEstimatorParams p = on();
	p.min_samples = 10;
	CSweepEstimator est(p, TScanMatcherParams(), 0.0);
	std::mt19937 rng(11);
	std::normal_distribution<double> noise(0.0, 0.002);
	std::uniform_real_distribution<double> rate(-1.0, 1.0), wild(-0.2, 0.2);
	for (int i = 0; i < 400; ++i)  // y = 10 ms * x, 20 % of the pairs wild
	{
		const double x = rate(rng);
		est.addSample(x, i % 5 == 0 ? wild(rng) : 0.010 * x + noise(rng), 0.002);
	}
	EXPECT_TRUE(est.summary().estimated);
	EXPECT_NEAR(est.sweepTime(), 0.010, 0.001);
}
