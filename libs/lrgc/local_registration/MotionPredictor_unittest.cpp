/* CMotionPredictor's constant-velocity model (no odometry): the last step's motion scaled by
 * the time ratio on a regular scan clock, so a dropped scan is bridged; one step per scan on a
 * jittered clock (timestamps running backwards in bursts, as in the Intel log), where the
 * time ratio would multiply a 5 deg step into 25 deg. And the odometry model's prior. */
#include <gtest/gtest.h>
#include <lrgc/local_registration/MotionPredictor.h>
#include <lrgc/common/se2.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/system/datetime.h>

#include <cmath>
#include <vector>

using namespace lrgc;
using mrpt::math::TPose2D;

namespace
{
constexpr double kStepPhi = 5 * M_PI / 180;  // [rad] turned per step
const TPose2D kStep(0.1, 0.0, kStepPhi);

mrpt::Clock::time_point at(double seconds)
{
	return mrpt::Clock::fromDouble(1000.0 + seconds);
}

/** A laser-only predictor fed scans at the given times, each after the motion kStep. */
CMotionPredictor fedAt(const std::vector<double>& times)
{
	TMotionPredictorParams p;
	p.use_odometry = false;
	CMotionPredictor predictor(p);
	for (const double t : times) predictor.commitScan(at(t), kStep);
	return predictor;
}
}  // namespace

TEST(MotionPredictor, regularClockScalesTheLastStepByTheTimeRatio)
{
	std::vector<double> times;
	for (int k = 0; k < 20; ++k) times.push_back(0.2 * k);
	const CMotionPredictor predictor = fedAt(times);
	EXPECT_FALSE(predictor.clockJittered());
	EXPECT_NEAR(predictor.scanPeriod(), 0.2, 1e-6);
	// Next scan on time: one step.
	const auto onTime = predictor.predict(at(times.back() + 0.2));
	EXPECT_FALSE(onTime.fromOdometry);
	EXPECT_NEAR(onTime.motion.phi, kStepPhi, 1e-6);
	EXPECT_NEAR(onTime.motion.x, 0.1, 1e-6);
	// One scan dropped: two steps' worth.
	const auto afterDrop = predictor.predict(at(times.back() + 0.4));
	EXPECT_NEAR(afterDrop.motion.phi, 2 * kStepPhi, 1e-6);
	EXPECT_NEAR(afterDrop.stepSeconds, 0.4, 1e-6);
}

TEST(MotionPredictor, irregularButMonotonicClockStillScales)
{
	// ACES logs scans every 0.07-0.32 s: true intervals, so the ratio applies.
	const CMotionPredictor predictor = fedAt({0.0, 0.16, 0.32, 0.40, 0.64, 0.80});
	EXPECT_FALSE(predictor.clockJittered());
	// The last step (0.16 s) turned kStepPhi; 0.08 s later: half of it.
	EXPECT_NEAR(predictor.predict(at(0.88)).motion.phi, 0.5 * kStepPhi, 1e-6);
}

TEST(MotionPredictor, jitteredClockPredictsOneStepPerScan)
{
	// Intel-like bursts: a regular 0.2 s clock, then timestamps bunched and running back.
	std::vector<double> times;
	for (int k = 0; k < 20; ++k) times.push_back(0.2 * k);
	for (const double t : {4.0, 4.001, 3.5, 4.6, 4.601}) times.push_back(t);
	const CMotionPredictor predictor = fedAt(times);
	EXPECT_TRUE(predictor.clockJittered());
	// 0.6 s after a 1 ms step: the time ratio would be 600 (capped before at 5 steps); the
	// scans arrive in order at their own rate, so one step.
	const auto p = predictor.predict(at(5.2));
	EXPECT_NEAR(p.motion.phi, kStepPhi, 1e-6);
	EXPECT_NEAR(p.motion.x, 0.1, 1e-6);
}

TEST(MotionPredictor, meanScanPeriodIsTheTrueRateOnAJitteredClock)
{
	// Scans every 0.2 s, logged in Intel-like bursts: three stamps per 0.6 s, 1 ms apart and
	// then 0.1 s back. No interval is the true one; the span over the count is.
	std::vector<double> times;
	for (int k = 0; k < 20; ++k)
		for (const double d : {0.0, 0.001, -0.1}) times.push_back(0.6 * k + d);
	const CMotionPredictor predictor = fedAt(times);
	EXPECT_TRUE(predictor.clockJittered());
	EXPECT_GT(std::abs(predictor.scanPeriod() - 0.2), 0.1);
	EXPECT_NEAR(predictor.meanScanPeriod(), 0.2, 0.015);  // the last stamp is 0.1 s early: 0.19
}

TEST(MotionPredictor, jitterIsForgottenAfterARegularStretch)
{
	std::vector<double> times{0.0, 0.2, 0.1, 0.4};  // one backward jump
	for (int k = 3; k < 60; ++k) times.push_back(0.2 * k);
	const CMotionPredictor predictor = fedAt(times);
	EXPECT_FALSE(predictor.clockJittered());
	EXPECT_NEAR(predictor.predict(at(times.back() + 0.4)).motion.phi, 2 * kStepPhi, 1e-6);
}

TEST(MotionPredictor, odometryPriorIsTheOdometryMotionWithProportionalNoise)
{
	CMotionPredictor predictor;
	predictor.addOdometryAbsolute(TPose2D(1.0, 2.0, 0.5));
	predictor.commitScan(at(0), TPose2D(0, 0, 0));
	predictor.addOdometryAbsolute(compose(TPose2D(1.0, 2.0, 0.5), TPose2D(0.3, 0.0, 0.1)));
	const auto p = predictor.predict(at(0.2));
	ASSERT_TRUE(p.fromOdometry);
	EXPECT_NEAR(p.motion.x, 0.3, 1e-9);
	EXPECT_NEAR(p.motion.y, 0.0, 1e-9);
	EXPECT_NEAR(p.motion.phi, 0.1, 1e-9);
	// sigma_xy = 0.01 + 0.1 * 0.3 + 0.05 * 0.1 = 0.045 m (defaults).
	EXPECT_NEAR(std::sqrt(p.cov(0, 0)), 0.045, 1e-9);
}

// Beyond noise_correlation_length_m (1 m), a straight odometry-only motion is a random walk:
// the distance terms' variance grows linearly, so 16 m is 4x the std of 1 m, not 16x.
TEST(MotionPredictor, odometryNoiseOfALongBlindStretchGrowsWithTheSquareRootOfDistance)
{
	const CMotionPredictor predictor;
	const auto distanceStd = [&](double d)
	{
		const Eigen::Matrix3d c = predictor.odometryCov(TPose2D(d, 0, 0));
		return Eigen::Vector2d(std::sqrt(c(0, 0)) - 0.01,
							   std::sqrt(c(2, 2)) - mrpt::DEG2RAD(0.5));
	};
	// Proportional up to 1 m: 0.1 m/m and 0.05 rad/m (defaults).
	EXPECT_NEAR(distanceStd(0.5).x(), 0.05, 1e-12);
	EXPECT_NEAR(distanceStd(1.0).y(), 0.05, 1e-12);
	// Continuous at 1 m, then sqrt(L d).
	EXPECT_NEAR(distanceStd(1.0 + 1e-9).x(), 0.1, 1e-9);
	EXPECT_NEAR(distanceStd(16.0).x(), 0.4, 1e-12);
	EXPECT_NEAR(distanceStd(16.0).y(), 0.2, 1e-12);
	EXPECT_NEAR(distanceStd(16.0).y() / distanceStd(4.0).y(), 2.0, 1e-12);
}

namespace
{
/** A predictor with odometry that committed scans every 0.2 s driving 0.1 m per step, the
 * odometry then reading `step` more `dt` seconds after the last scan. */
lrgc::TMotionPrediction afterOdometryStep(const TPose2D& step, double dt)
{
	CMotionPredictor predictor;
	TPose2D odom(5.0, -3.0, 1.0);
	for (int k = 0; k < 10; ++k)
	{
		odom = compose(odom, TPose2D(0.1, 0, 0));
		predictor.addOdometryAbsolute(odom);
		predictor.commitScan(at(0.2 * k), TPose2D(0.1, 0, 0));
	}
	predictor.addOdometryAbsolute(compose(odom, step));
	return predictor.predict(at(1.8 + dt));
}
}  // namespace

// A reboot of the base restarts its odometry at (0, 0, 0): a step of metres or of more than
// the glitch search's 90 deg in one scan interval is the odometry's frame changing, not
// motion. The step is then predicted by constant velocity, and flagged.
TEST(MotionPredictor, anOdometryJumpIsPredictedByConstantVelocity)
{
	for (const TPose2D& jump :
		 {TPose2D(-6.0, 1.0, 0.2), TPose2D(0.3, 0.1, mrpt::DEG2RAD(150)), TPose2D(2.3, 0, 0)})
	{
		const auto p = afterOdometryStep(jump, 0.1);  // beyond 2 m + 2 m/s * 0.1 s = 2.2 m
		EXPECT_TRUE(p.odometryJump) << jump.asString();
		EXPECT_FALSE(p.fromOdometry);
		EXPECT_NEAR(p.motion.x, 0.1 * 0.5, 1e-9);  // the last step, over half its interval
		EXPECT_NEAR(p.odometryStep.x, jump.x, 1e-9);
		EXPECT_NEAR(p.odometryStep.phi, jump.phi, 1e-9);
	}
}

// What a robot can drive is odometry: the benchmark logs' largest steps (0.95 m, 61 deg), a
// glitch turning 85 deg (the registration's wide search handles it), and 5 m after a 5 s
// pause in the scans.
TEST(MotionPredictor, largeButPossibleStepsAreOdometry)
{
	for (const auto& [step, dt] : {std::pair{TPose2D(0.95, 0, mrpt::DEG2RAD(7.6)), 0.21},
								   std::pair{TPose2D(0.38, 0, mrpt::DEG2RAD(61)), 0.16},
								   std::pair{TPose2D(0.1, 0, mrpt::DEG2RAD(-85)), 0.0},
								   std::pair{TPose2D(5.0, 0.5, mrpt::DEG2RAD(90)), 5.0},
								   std::pair{TPose2D(2.1, 0, 0), 0.1}})
	{
		const auto p = afterOdometryStep(step, dt);
		EXPECT_FALSE(p.odometryJump) << step.asString() << " in " << dt << " s";
		EXPECT_TRUE(p.fromOdometry);
		EXPECT_NEAR(p.motion.x, step.x, 1e-9);
	}
}

// A one-reading glitch: the odometry of one scan reads 80 deg more turn, the scan is placed
// off it (a wide search found the truth, 5 deg), and the next reading is right again (-75 deg
// from the glitched one). The prediction is that -75 deg step from the scan as placed; the
// alternative, the odometry since the last scan that followed it (10 deg in all), expressed
// from the scan as placed: +5 deg. None while every scan follows its odometry, none once the
// last that did lies more than two scans back.
TEST(MotionPredictor, aScanPlacedOffItsOdometryLeavesTheOdometrySinceTheLastThatWasNot)
{
	CMotionPredictor predictor;
	TPose2D odom(5.0, -3.0, 1.0);
	for (int k = 0; k < 5; ++k)
	{
		odom = compose(odom, TPose2D(0.1, 0, 0));
		predictor.addOdometryAbsolute(odom);
		EXPECT_FALSE(predictor.predict(at(0.2 * k)).alternative.has_value());
		predictor.commitScan(at(0.2 * k), TPose2D(0.1, 0, 0));
	}
	const TPose2D trueTurn(0, 0, mrpt::DEG2RAD(5));
	predictor.addOdometryAbsolute(compose(odom, TPose2D(0, 0, mrpt::DEG2RAD(85))));
	predictor.commitScan(at(1.0), trueTurn, false);  // placed off its odometry
	odom = compose(odom, TPose2D(0, 0, mrpt::DEG2RAD(10)));
	predictor.addOdometryAbsolute(odom);
	const auto p = predictor.predict(at(1.2));
	EXPECT_TRUE(p.fromOdometry);
	EXPECT_NEAR(p.motion.phi, mrpt::DEG2RAD(-75), 1e-9);
	ASSERT_TRUE(p.alternative.has_value());
	EXPECT_NEAR(p.alternative->motion.phi, mrpt::DEG2RAD(5), 1e-9);
	EXPECT_NEAR(p.alternative->cov(2, 2),
				predictor.odometryCov(TPose2D(0, 0, 0.1745)).coeff(2, 2), 1e-4);
	predictor.commitScan(at(1.2), trueTurn, false);  // two scans off their odometry
	EXPECT_TRUE(predictor.predict(at(1.4)).alternative.has_value());
	predictor.commitScan(at(1.4), trueTurn, false);  // three
	EXPECT_FALSE(predictor.predict(at(1.6)).alternative.has_value());
}
