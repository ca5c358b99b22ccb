/* Free space: a straight wall 4 m ahead seen by a scan; points in front of it are in free
 * space, points behind it or beyond the scan's field of view are not. */
#include <gtest/gtest.h>
#include <lrgc/scan_matching/FreeSpace.h>
#include <lrgc/scan_matching/Scan.h>

#include <cmath>
#include <random>
#include <utility>
#include <vector>

using namespace lrgc;

namespace
{
/** A wall x = 4 m seen over bearings -40..40 deg, one return per 0.5 deg. */
TScan2D wallScan()
{
	TScan2D s;
	for (double a = -40; a <= 40; a += 0.5)
	{
		const double t = a * M_PI / 180;
		s.points.emplace_back(4.0, 4.0 * std::tan(t));
	}
	return s;
}
}  // namespace

TEST(FreeSpace, rangeImageKnowsWhatTheBeamsCrossed)
{
	const CRangeImage img(wallScan().points);
	bool known = false;
	EXPECT_TRUE(img.inFreeSpace({2.0, 0.0}, 0.1, &known));
	EXPECT_TRUE(known);
	EXPECT_FALSE(img.inFreeSpace({3.95, 0.0}, 0.1, &known)) << "within the margin of the wall";
	EXPECT_FALSE(img.inFreeSpace({6.0, 1.0}, 0.1, &known)) << "behind the wall";
	EXPECT_FALSE(img.inFreeSpace({-2.0, 0.0}, 0.1, &known)) << "no beam went backwards";
	EXPECT_FALSE(known);
}

TEST(FreeSpace, aScanPushedIntoSeenFreeSpaceViolatesItAndTheTrueOneDoesNot)
{
	CFreeSpaceViews views;
	EXPECT_DOUBLE_EQ(views.scanViolation(wallScan(), {0, 0, 0}, 0.1), 0.0) << "no views yet";
	views.add(wallScan(), {0, 0, 0});
	EXPECT_DOUBLE_EQ(views.scanViolation(wallScan(), {0, 0, 0}, 0.1), 0.0);
	// The same wall placed 1.5 m nearer (x = 2.5 m): the points the view's +-40 deg beams
	// crossed (|y| < 2.1 m, 68 % of them) lie in its free space, the outer ones it never saw.
	const double v = views.scanViolation(wallScan(), {-1.5, 0, 0}, 0.1);
	EXPECT_GT(v, 0.6);
	EXPECT_LT(v, 0.75);
	// Placed farther away: behind the seen wall, unknown space, no violation.
	EXPECT_DOUBLE_EQ(views.scanViolation(wallScan(), {1.5, 0, 0}, 0.1), 0.0);
}

// A crowd's count ([LocalRegistration] crowd_min_run_m): the wall seen at x = 4 m, and a scan
// of it with a person (a 0.4 m blob at x = 2 m) in the view's free space, and one with a
// 3 m piece of wall 1.5 m too near. With runs of 0.8 m at least only the wall piece counts.
TEST(FreeSpace, aPersonIsAShortRunAndAMisplacedWallALongOne)
{
	CFreeSpaceViews views;
	views.add(wallScan(), {0, 0, 0});
	TScan2D person = wallScan(), misplaced = wallScan();
	for (double y = -0.2; y <= 0.2 + 1e-9; y += 0.05)  // 9 returns off the person
		person.points.emplace_back(2.0, y);
	for (auto& p : misplaced.points)
		if (std::abs(p.y()) < 1.5) p.x() = 2.5;  // the middle 3 m of the wall, 1.5 m too near
	auto share = [&](const TScan2D& scan, double minRun)
	{
		CScanViolation v(views, scan, {0, 0, 0}, 0.1);
		v.flag(0, v.size());
		return v.share(minRun);
	};
	EXPECT_NEAR(share(person, 0), 9.0 / person.points.size(), 1e-12);
	EXPECT_DOUBLE_EQ(share(person, 0.8), 0.0) << "a 0.4 m run";
	const double wall = share(misplaced, 0);
	EXPECT_GT(wall, 0.4);
	EXPECT_DOUBLE_EQ(share(misplaced, 0.8), wall) << "one 3 m run";
}

// The still robot's check (CLocalRegistration::stillRegistration): the same view changes by
// nothing, a person 1 m away across a fifth of it does not move the median, a step of 5 cm
// towards the wall changes it by 5-7 cm (5 cm / cos(bearing)), and a view half gone shares half
// its bins.
TEST(FreeSpace, medianChangeIsTheTypicalRangeChangeOverTheBinsBothSee)
{
	const TScan2D wall = wallScan();
	const CRangeImage img(wall.points);
	EXPECT_EQ(img.medianChange(img), std::make_pair(0.0, 1.0));

	TScan2D people = wall;
	for (size_t i = 0; i < people.points.size() / 5; ++i) people.points[i] *= 0.25;
	EXPECT_LT(img.medianChange(CRangeImage(people.points)).first, 1e-6);

	TScan2D nearer = wall;
	for (auto& p : nearer.points) p *= 3.95 / 4.0;
	const auto [change, shared] = img.medianChange(CRangeImage(nearer.points));
	EXPECT_GT(change, 0.05 - 1e-6);
	EXPECT_LT(change, 0.05 / std::cos(40 * M_PI / 180));
	EXPECT_DOUBLE_EQ(shared, 1.0);

	TScan2D half = wall;
	half.points.resize(wall.points.size() / 2);
	const double halfShared = img.medianChange(CRangeImage(half.points)).second;
	EXPECT_GT(halfShared, 0.45);
	EXPECT_LT(halfShared, 0.55);
	EXPECT_EQ(img.medianChange(CRangeImage({})).second, 0.0) << "nothing seen in both";
}

TEST(FreeSpace, bearingBinIsTheAtan2FormulaEverywhere)
{
	const double bin = M_PI / 180;
	auto exact = [&](double x, double y)
	{ return static_cast<long>((std::atan2(y, x) + M_PI) / bin); };
	std::vector<std::pair<double, double>> dirs = {
		{1, 0}, {-1, 0}, {-1, -0.0}, {0, 1},  {0, -1},      {0, 0},        {-0.0, 0},
		{1, 1}, {-1, 1}, {-1, -1},   {1, -1}, {-5, 1e-300}, {-5, -1e-300}, {3, 1e-17}};
	// Every bin border, on it and just either side of it (down to 1e-15 rad), at 3 ranges.
	for (int b = 0; b <= 360; ++b)
		for (const double off : {0.0, 1e-15, -1e-15, 1e-10, -1e-10, 1e-8, -1e-8, 1.2e-5,
								 -1.2e-5, 2e-5, -2e-5, 2.5e-5, -2.5e-5, 1e-4, -1e-4, 0.5 * bin})
			for (const double r : {0.05, 3.7, 81.0})
			{
				const double t = b * bin - M_PI + off;
				dirs.emplace_back(r * std::cos(t), r * std::sin(t));
			}
	std::mt19937 rng(3);
	std::uniform_real_distribution<double> u(-30, 30);
	for (int i = 0; i < 200000; ++i) dirs.emplace_back(u(rng), u(rng));
	size_t checked = 0;
	for (const auto& [x, y] : dirs)
	{
		ASSERT_EQ(bearingBin(x, y), exact(x, y)) << "direction (" << x << ", " << y << ")";
		++checked;
	}
	EXPECT_GT(checked, 200000u);
}

TEST(FreeSpace, scansOwnRangeImageIsUsedOnlyWhileItMatchesThePoints)
{
	TScan2D s = wallScan();
	s.rangeImage = std::make_shared<const CRangeImage>(s.points);
	EXPECT_EQ(rangeImageOf(s), s.rangeImage);  // shared, not rebuilt
	// Points changed without resetting the image: rebuilt from the points.
	s.points.resize(s.points.size() / 2);
	const auto img = rangeImageOf(s);
	EXPECT_NE(img, s.rangeImage);
	EXPECT_EQ(img->numPoints(), s.points.size());
	// The half scan (bearings -40..0 deg) saw nothing to the left: unknown there.
	bool known = true;
	EXPECT_FALSE(img->inFreeSpace({2, 1}, 0.1, &known));
	EXPECT_FALSE(known);
	EXPECT_TRUE(s.rangeImage->inFreeSpace({2, 1}, 0.1, &known));
}
