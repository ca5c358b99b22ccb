/* CAnchorGrid against brute force: nearest and radius queries on random points, cells of
 * several sizes, queries inside and outside the cloud, unusable points never returned. */
#include <gtest/gtest.h>
#include <lrgc/scan_matching/AnchorGrid.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>

using namespace lrgc;

namespace
{
struct TCloud
{
	std::vector<Eigen::Vector2d> pts;
	std::vector<bool> usable;
};

TCloud randomCloud(size_t n, uint32_t seed)
{
	std::mt19937 rng(seed);
	std::uniform_real_distribution<double> u(-5, 5);
	std::bernoulli_distribution keep(0.8);
	TCloud c;
	for (size_t i = 0; i < n; ++i)
		c.pts.emplace_back(u(rng), u(rng)), c.usable.push_back(keep(rng));
	return c;
}
}  // namespace

TEST(AnchorGrid, nearestEqualsBruteForceWithinTheGate)
{
	const TCloud c = randomCloud(2000, 7);
	std::mt19937 rng(8);
	std::uniform_real_distribution<double> u(-7, 7);
	for (const double cell : {0.05, 0.3, 2.0})
	{
		const CAnchorGrid grid(c.pts, c.usable, cell);
		for (int t = 0; t < 500; ++t)
		{
			const Eigen::Vector2d q(u(rng), u(rng));
			const double gate = 0.4;
			double best = gate * gate;
			int expected = -1;
			for (size_t i = 0; i < c.pts.size(); ++i)
				if (c.usable[i] && (c.pts[i] - q).squaredNorm() < best)
					best = (c.pts[i] - q).squaredNorm(), expected = static_cast<int>(i);
			double d2 = -1;
			const int got = grid.nearest(q, gate, &d2);
			ASSERT_EQ(got, expected) << "cell " << cell << " query " << q.transpose();
			if (got >= 0)
			{
				EXPECT_DOUBLE_EQ(d2, best);
			}
		}
	}
}

TEST(AnchorGrid, forEachWithinVisitsExactlyTheUsablePointsInTheDisc)
{
	const TCloud c = randomCloud(1000, 9);
	const CAnchorGrid grid(c.pts, c.usable, 0.25);
	for (const Eigen::Vector2d& q :
		 {Eigen::Vector2d(0, 0), Eigen::Vector2d(4.9, -4.9), Eigen::Vector2d(9, 9)})
	{
		std::set<size_t> got, expected;
		grid.forEachWithin(q, 0.8, [&](uint32_t i) { got.insert(i); });
		for (size_t i = 0; i < c.pts.size(); ++i)
			if (c.usable[i] && (c.pts[i] - q).norm() <= 0.8) expected.insert(i);
		EXPECT_EQ(got, expected);
		// forEachPointWithin: the same points, in the same order, each with its position.
		std::vector<uint32_t> order, orderWithPos;
		grid.forEachWithin(q, 0.8, [&](uint32_t i) { order.push_back(i); });
		grid.forEachPointWithin(q, 0.8,
								[&](uint32_t i, const Eigen::Vector2d& p)
								{
									orderWithPos.push_back(i);
									EXPECT_EQ(p, c.pts[i]);
								});
		EXPECT_EQ(orderWithPos, order);
	}
}

TEST(AnchorGrid, emptyAndUnusableCloudsFindNothing)
{
	EXPECT_EQ(CAnchorGrid().nearest({0, 0}, 1.0), -1);
	const CAnchorGrid none({{0, 0}, {0.1, 0}}, {false, false}, 0.1);
	EXPECT_EQ(none.nearest({0, 0}, 1.0), -1);
	const CAnchorGrid one({{0, 0}}, {true}, 0.1);
	EXPECT_EQ(one.nearest({0.05, 0}, 0.0), -1) << "a zero gate finds nothing";
	EXPECT_EQ(one.nearest({0.05, 0}, 0.1), 0);
}

TEST(AnchorGrid, denseAndHashedCellsGiveTheSameAnswers)
{
	// The same cloud indexed through the dense table, and through the hash table once two
	// far stray returns make its bounding box too large for a dense one.
	const TCloud c = randomCloud(1500, 11);
	TCloud stray = c;
	stray.pts.emplace_back(4000, -3000), stray.usable.push_back(true);
	stray.pts.emplace_back(-4000, 3000), stray.usable.push_back(true);
	const CAnchorGrid dense(c.pts, c.usable, 0.1), hashed(stray.pts, stray.usable, 0.1);
	ASSERT_TRUE(dense.isDense());
	ASSERT_FALSE(hashed.isDense());
	std::mt19937 rng(12);
	std::uniform_real_distribution<double> u(-6, 6);
	for (int t = 0; t < 2000; ++t)
	{
		const Eigen::Vector2d q(u(rng), u(rng));
		for (const double gate : {0.02, 0.3, 1.5})
		{
			double d2a = -1, d2b = -1;
			const int a = dense.nearest(q, gate, &d2a), b = hashed.nearest(q, gate, &d2b);
			ASSERT_EQ(a, b) << "query " << q.transpose() << " gate " << gate;
			if (a >= 0)
			{
				EXPECT_EQ(d2a, d2b);
			}
		}
		std::vector<uint32_t> inDense, inHashed;
		dense.forEachWithin(q, 0.3, [&](uint32_t i) { inDense.push_back(i); });
		hashed.forEachWithin(q, 0.3, [&](uint32_t i) { inHashed.push_back(i); });
		std::sort(inDense.begin(), inDense.end());
		std::sort(inHashed.begin(), inHashed.end());
		ASSERT_EQ(inDense, inHashed);
	}
	EXPECT_EQ(hashed.nearest({4000.01, -3000}, 0.1), static_cast<int>(c.pts.size()));
	EXPECT_EQ(dense.nearest({4000.01, -3000}, 0.1), -1);
}

TEST(AnchorGrid, nearestWithBoundAnswersAsNearestAndBoundsEveryOtherPoint)
{
	// The bound the scan matcher's warm association relies on: no usable point other than the
	// answer (none: no usable point at all) is closer than it, through the dense table, the
	// hash table and the radiusOnly grid's full scan; and it is not vacuous near the points.
	const TCloud c = randomCloud(1500, 21);
	TCloud stray = c;
	stray.pts.emplace_back(4000, -3000), stray.usable.push_back(true);
	const CAnchorGrid dense(c.pts, c.usable, 0.3), hashed(stray.pts, stray.usable, 0.3),
		scanOnly(c.pts, c.usable, 0.3, true);
	ASSERT_TRUE(dense.isDense());
	ASSERT_FALSE(hashed.isDense());
	std::mt19937 rng(22);
	std::uniform_real_distribution<double> u(-6, 6);
	int useful = 0, found = 0;
	for (int t = 0; t < 1500; ++t)
		for (const double gate : {0.02, 0.3, 1.5})
		{
			const Eigen::Vector2d q(u(rng), u(rng));
			for (const auto* g : {&dense, &hashed, &scanOnly})
			{
				const TCloud& cl = g == &hashed ? stray : c;
				double bound = -1;
				const int j = g->nearestWithBound(q, gate, &bound);
				ASSERT_EQ(j, g->nearest(q, gate)) << "query " << q.transpose();
				double other = std::numeric_limits<double>::infinity();
				for (size_t i = 0; i < cl.pts.size(); ++i)
					if (cl.usable[i] && static_cast<int>(i) != j)
						other = std::min(other, (cl.pts[i] - q).norm());
				ASSERT_LE(bound, other + 1e-12)
					<< "query " << q.transpose() << " gate " << gate;
				if (j >= 0) ++found, useful += bound > (cl.pts[j] - q).norm();
			}
		}
	ASSERT_GT(found, 1000);
	EXPECT_GT(useful, found * 9 / 10) << "the bound should mostly exceed the answer's distance";
	double bound = -1;
	EXPECT_EQ(dense.nearestWithBound({100, 100}, 0.5, &bound), -1);
	EXPECT_EQ(bound, 0.5) << "a query far from the box: every point beyond the gate";
	EXPECT_EQ(dense.nearestWithBound({NAN, 0}, 0.5, &bound), -1);
	EXPECT_EQ(bound, 0.0);
}

TEST(AnchorGrid, forEachWithinVisitsCellsInColumnMajorOrderDenseOrHashed)
{
	// The line fits sum their neighbourhoods in visiting order: cells by (ix, then iy), on
	// the dense table's column runs as on the hash table's cells.
	const TCloud c = randomCloud(1500, 13);
	TCloud stray = c;
	stray.pts.emplace_back(5000, 5000), stray.usable.push_back(true);
	const double cell = 0.1;
	for (const TCloud* cloud : std::vector<const TCloud*>{&c, &stray})
	{
		const CAnchorGrid grid(cloud->pts, cloud->usable, cell);
		EXPECT_EQ(grid.isDense(), cloud == &c);
		for (const Eigen::Vector2d& q :
			 {Eigen::Vector2d(0.03, -1.2), Eigen::Vector2d(-4.5, 4.6)})
		{
			std::vector<std::pair<int64_t, int64_t>> cells;
			grid.forEachWithin(q, 1.5,
							   [&](uint32_t i)
							   {
								   cells.emplace_back(
									   CAnchorGrid::cellIndex(cloud->pts[i].x(), cell),
									   CAnchorGrid::cellIndex(cloud->pts[i].y(), cell));
							   });
			EXPECT_GT(cells.size(), 20u);
			EXPECT_TRUE(std::is_sorted(cells.begin(), cells.end()));
		}
	}
}

TEST(AnchorGrid, forEachRunFilteredIsForEachPointWithinDenseHashedOrAbsurd)
{
	// The line fits and the covariance's fit terms read the runs themselves and filter by
	// distance: they must see forEachPointWithin's points in its order, index for index.
	const TCloud c = randomCloud(1500, 17);
	TCloud stray = c;
	stray.pts.emplace_back(5000, -5000), stray.usable.push_back(true);
	for (const TCloud* cloud : std::vector<const TCloud*>{&c, &stray})
	{
		const CAnchorGrid grid(cloud->pts, cloud->usable, 0.1);
		EXPECT_EQ(grid.isDense(), cloud == &c);
		std::mt19937 rng(18);
		std::uniform_real_distribution<double> u(-6, 6);
		size_t within06 = 0;  // points seen at radius 0.6, over all queries
		for (int t = 0; t < 300; ++t)
		{
			const Eigen::Vector2d q(u(rng), u(rng));
			// 1e6 m: more cells than kMaxVisitedCells, every point read.
			for (const double radius : {0.15, 0.6, 2.0, 1e6})
			{
				std::vector<uint32_t> want, got;
				grid.forEachPointWithin(q, radius,
										[&](uint32_t i, const Eigen::Vector2d& p)
										{
											want.push_back(i);
											EXPECT_EQ(p, cloud->pts[i]);
										});
				const auto& pos = grid.cellPoints();
				const auto& index = grid.cellIndices();
				grid.forEachRun(q, radius,
								[&](uint32_t b, uint32_t e)
								{
									ASSERT_LE(b, e);
									ASSERT_LE(e, pos.size());
									for (uint32_t k = b; k < e; ++k)
										if ((pos[k] - q).squaredNorm() <= radius * radius)
											got.push_back(index[k]);
								});
				ASSERT_EQ(want, got) << "query " << q.transpose() << " radius " << radius;
				within06 += radius == 0.6 ? want.size() : 0;
			}
		}
		// ~ 300 queries x 12 usable points / m^2 x 1.13 m^2 x 0.69 (queries over the cloud)
		EXPECT_GT(within06, 2000u);
	}
}

TEST(AnchorGrid, hashedRadiusQueryReadsAColumnAsOneRun)
{
	// A far stray return makes the grid hashed; the line fits' radius queries then read a
	// column's occupied cells through the column directory as one run (two where the cells
	// straddle iy = 0, whose keys sort after the others'), not cell by cell (main: a run per
	// occupied cell, ~10 per column here). A stray too far for the directory (more columns
	// than kDenseCellsPerPoint per point) reads cell by cell.
	const TCloud c = randomCloud(20000, 21);  // 160 usable points / m^2
	for (const double strayX : {5000.0, 1e6})
	{
		TCloud stray = c;
		stray.pts.emplace_back(strayX, 0), stray.usable.push_back(true);
		const CAnchorGrid grid(stray.pts, stray.usable, 0.1);
		ASSERT_FALSE(grid.isDense());
		for (const Eigen::Vector2d& q : {Eigen::Vector2d(1.03, 2.2), Eigen::Vector2d(-2, 0.04)})
		{
			size_t runs = 0, points = 0;
			grid.forEachRun(q, 0.6, [&](uint32_t b, uint32_t e) { ++runs, points += e - b; });
			const size_t columns = 13;  // cells x within 0.6 m of q: at most 13 of 0.1 m
			if (strayX < 1e5)
				EXPECT_LE(runs, q.y() > 0.6 ? columns : 2 * columns);
			else
				EXPECT_GT(runs, 2 * columns);
			EXPECT_GT(points, 150u);  // the query's box: ~1.44 m^2
		}
	}
}

TEST(AnchorGrid, cellIndexIsFloorOfTheRatio)
{
	for (const double v : {0.0, -0.0, 0.1, -0.1, 0.3, -0.3, 0.29999999999999999, 1e-300,
						   -1e-300, 123.456, -123.456, 1e6, -1e6, 0.7, -0.7})
		for (const double cell : {0.1, 0.02, 0.3, 1.0})
			EXPECT_EQ(CAnchorGrid::cellIndex(v, cell),
					  static_cast<int64_t>(std::floor(v / cell)))
				<< v << " / " << cell;
}

TEST(AnchorGrid, equallyNearPointsResolvedAsTheRingWalkDoes)
{
	// Pairs of exactly representable points equally near a query, on its upper left and
	// lower right (the ring walk meets the upper left one first, a row-by-row reading the
	// lower right one), around many queries: the dense table (rings read as row and column
	// runs) keeps the point the hash table's cell-by-cell ring walk finds first.
	TCloud c;
	std::vector<Eigen::Vector2d> queries;
	for (int i = -30; i <= 30; i += 3)
		for (int j = -30; j <= 30; j += 3)
		{
			const Eigen::Vector2d q(0.25 * i + 0.0625 * (j & 3), 0.25 * j + 0.0625 * (i & 3));
			queries.push_back(q);
			for (const double a : {0.125, 0.1875})
			{
				c.pts.push_back(q + Eigen::Vector2d(-a, a)), c.usable.push_back(true);
				c.pts.push_back(q + Eigen::Vector2d(a, -a)), c.usable.push_back(true);
			}
		}
	TCloud stray = c;
	stray.pts.emplace_back(5000, 5000), stray.usable.push_back(true);
	const CAnchorGrid dense(c.pts, c.usable, 0.1), hashed(stray.pts, stray.usable, 0.1);
	ASSERT_TRUE(dense.isDense());
	ASSERT_FALSE(hashed.isDense());
	int upperLeft = 0;
	for (size_t t = 0; t < queries.size(); ++t)
	{
		const int got = dense.nearest(queries[t], 0.5);
		ASSERT_EQ(got, hashed.nearest(queries[t], 0.5)) << queries[t].transpose();
		EXPECT_TRUE(got == static_cast<int>(4 * t) || got == static_cast<int>(4 * t + 1));
		upperLeft += got == static_cast<int>(4 * t);
	}
	EXPECT_GT(upperLeft, 0);
}

// Issue 30: far but finite points (1e25 m, a scan's absurd reading) overflowed the int64 cell
// indices (a crash in buildDense, an endless findCell); NaN queries or points and a huge
// maxDist sent nearest() round its rings for ever. Each case must end, and answer as brute
// force over the sane points does. Timed by ctest's time-out, not here.
TEST(AnchorGrid, FarNonFiniteAndAbsurdInputsEndAndAnswerRight)
{
	TCloud c = randomCloud(300, 11);
	const size_t sane = c.pts.size();
	const double nan = std::numeric_limits<double>::quiet_NaN();
	for (const Eigen::Vector2d& far :
		 {Eigen::Vector2d(1e25, 3), Eigen::Vector2d(-1e20, 1e20), Eigen::Vector2d(nan, 0),
		  Eigen::Vector2d(0, std::numeric_limits<double>::infinity()), Eigen::Vector2d(2e7, 0)})
		c.pts.push_back(far), c.usable.push_back(true);
	for (const double cell : {0.05, 0.3})
	{
		const CAnchorGrid grid(c.pts, c.usable, cell);
		for (const Eigen::Vector2d& q :
			 {Eigen::Vector2d(0.1, 0.2), Eigen::Vector2d(1e25, 3), Eigen::Vector2d(nan, nan),
			  Eigen::Vector2d(-3e30, 0), Eigen::Vector2d(4.0, -6.0)})
			for (const double maxDist : {0.5, 3.0, 1e30})
			{
				int expected = -1;
				double best = maxDist * maxDist;
				for (size_t i = 0; i < sane; ++i)
					if (c.usable[i] && (c.pts[i] - q).squaredNorm() < best)
						best = (c.pts[i] - q).squaredNorm(), expected = static_cast<int>(i);
				// Far queries see many points equally near (d2 rounds to the same double):
				// any of them is right.
				const int got = grid.nearest(q, maxDist);
				ASSERT_EQ(got >= 0, expected >= 0)
					<< "cell " << cell << " q " << q.transpose() << " maxDist " << maxDist;
				if (got >= 0)
				{
					ASSERT_LT(size_t(got), sane) << "an absurd point was indexed";
					EXPECT_EQ((c.pts[size_t(got)] - q).squaredNorm(), best) << q.transpose();
				}
				size_t within = 0;
				grid.forEachWithin(q, std::min(maxDist, 1e3),
								   [&](uint32_t i)
								   {
									   EXPECT_LT(i, sane) << "an absurd point was indexed";
									   ++within;
								   });
			}
	}
}
