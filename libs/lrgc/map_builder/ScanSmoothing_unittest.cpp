/* smoothScans: the scans between keyframes, placed by their registration and the odometry.
 * A straight drive of 0.25 m steps, a keyframe every 4th scan; registered poses 5 mm from the
 * truth (covariance 1 mm^2 unless said), odometry 5 mm per step off; the model's covariance
 * the motion predictor's default for such a step (3.5 cm, 1.2 deg). */
#include <gtest/gtest.h>

#include <lrgc/common/se2.h>
#include <lrgc/map_builder/ScanSmoothing.h>

#include <random>

namespace
{
using lrgc::TScanStep;
using mrpt::math::TPose2D;

/** n scans along x, 0.25 m apart; `truth` receives the true poses. */
std::vector<TScanStep> straightDrive(size_t n, std::vector<TPose2D>& truth, uint32_t seed)
{
	std::mt19937 rng(seed);
	std::normal_distribution<double> reg(0, 0.005), odo(0, 0.005), odoPhi(0, 0.002);
	std::vector<TScanStep> s(n);
	truth.assign(n, TPose2D(0, 0, 0));
	for (size_t k = 0; k < n; ++k)
	{
		truth[k] = TPose2D(0.25 * double(k), 0, 0);
		s[k].pose = TPose2D(truth[k].x + reg(rng), truth[k].y + reg(rng), 0.001 * reg(rng));
		s[k].odometryStep = TPose2D(0.25 + odo(rng), odo(rng), odoPhi(rng));
		s[k].stepCov =
			Eigen::Vector3d(0.035 * 0.035, 0.035 * 0.035, 0.021 * 0.021).asDiagonal();
		s[k].poseCov = Eigen::Vector3d(1e-6, 1e-6, 1e-6).asDiagonal();
		s[k].fromOdometry = k > 0;
		s[k].keyframe = k % 4 == 0;
	}
	return s;
}

double offTruth(const TPose2D& p, const TPose2D& truth)
{
	return lrgc::translationNorm(lrgc::between(truth, p));
}
}  // namespace

TEST(ScanSmoothing, ConsistentScansStayAndKeyframesAreLeftAlone)
{
	std::vector<TPose2D> truth;
	const auto s = straightDrive(200, truth, 1);
	const Eigen::Vector3d scale = lrgc::odometryNoiseScale(s);
	EXPECT_LT(scale.maxCoeff(), 0.4);  // the odometry's true spread, far below the model's
	const auto smoothed = lrgc::smoothScans(s, scale);
	EXPECT_EQ(smoothed.size(), 150U);
	for (const auto& [k, pose] : smoothed)
	{
		EXPECT_FALSE(s[k].keyframe);
		EXPECT_LT(offTruth(pose, s[k].pose), 0.01) << "scan " << k;
	}
}

TEST(ScanSmoothing, AnUncertainScanFollowsTheOdometryAPinnedOneStays)
{
	std::vector<TPose2D> truth;
	auto s = straightDrive(200, truth, 2);
	// Scan 101: 0.1 m sideways, its registration unsure (5 cm std); scan 105 as far off,
	// but its registration pins it (1 mm std).
	for (const size_t k : {101, 105}) s[k].pose = lrgc::compose(s[k].pose, TPose2D(0, 0.1, 0));
	s[101].poseCov = Eigen::Vector3d(0.05 * 0.05, 0.05 * 0.05, 1e-4).asDiagonal();
	const auto smoothed = lrgc::smoothScans(s, lrgc::odometryNoiseScale(s));
	for (const auto& [k, pose] : smoothed)
	{
		if (k == 101)
		{
			EXPECT_LT(offTruth(pose, truth[k]), 0.02);
		}
		if (k == 105)
		{
			EXPECT_GT(offTruth(pose, truth[k]), 0.09);
		}
		EXPECT_DOUBLE_EQ(pose.phi, s[k].pose.phi) << "the heading is the registration's";
	}
}

TEST(ScanSmoothing, AScanOffItsOdometryFollowsItOnceTheStepsAreWeighedAtTheNewPoses)
{
	// Scan 102: 0.1 m sideways, its registration 2 cm std (5 std off), the odometry's
	// calibrated spread 9 mm: at the registered poses the two steps into and out of it are
	// off by 11 std. Weighed there once, as outliers, they left it 0.051 m off; weighed anew
	// at each Gauss-Newton step (IRLS) it comes within 0.010 m.
	std::vector<TPose2D> truth;
	auto s = straightDrive(200, truth, 3);
	s[102].pose = lrgc::compose(s[102].pose, TPose2D(0, 0.1, 0));
	s[102].poseCov = Eigen::Vector3d(0.02 * 0.02, 0.02 * 0.02, 1e-4).asDiagonal();
	bool seen = false;
	for (const auto& [k, pose] : lrgc::smoothScans(s, lrgc::odometryNoiseScale(s)))
		if (k == 102)
		{
			seen = true;
			EXPECT_LT(offTruth(pose, truth[k]), 0.03);
		}
	EXPECT_TRUE(seen);
}

TEST(ScanSmoothing, StepsTheWheelsDidNotMakeLeaveTheOdometrysCalibrationAsItWas)
{
	// The drive with a stop after every scan: 200 zero steps whose registration agrees with
	// them exactly (a still robot's reused match). They say nothing of the odometry's noise;
	// counted, half the steps would read e = 0 and the median would calibrate it to the floor.
	std::vector<TPose2D> truth;
	const auto drive = straightDrive(200, truth, 4);
	std::vector<TScanStep> stops;
	for (const TScanStep& step : drive)
	{
		stops.push_back(step);
		TScanStep still = step;
		still.odometryStep = TPose2D(0, 0, 0);
		still.fromOdometry = true;
		still.keyframe = false;
		stops.push_back(still);
	}
	const Eigen::Vector3d moving = lrgc::odometryNoiseScale(drive);
	const Eigen::Vector3d withStops = lrgc::odometryNoiseScale(stops);
	EXPECT_GT(moving.minCoeff(), 0.05);
	EXPECT_TRUE(withStops.isApprox(moving, 0.1))
		<< withStops.transpose() << " against " << moving.transpose();
}
