#include <gtest/gtest.h>
#include <mrpt/core/exceptions.h>

#include <lrgc/loop_closing/CorrelationGrid.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

using lrgc::CCorrelationGrid;

namespace
{
// Centre [m] of the cell (dx, dy) cells away from the cell containing p.
Eigen::Vector2d cellCentre(const CCorrelationGrid& g, const Eigen::Vector2d& p, int dx, int dy)
{
	const Eigen::Vector2i c = g.cellOf(p) + Eigen::Vector2i(dx, dy);
	return g.origin() + (c.cast<double>() + Eigen::Vector2d(0.5, 0.5)) * g.resolution();
}
}  // namespace

TEST(CorrelationGrid, BlurIsGaussianOfDistanceToNearestPoint)
{
	const double res = 0.05, sigma = 0.1;
	const std::vector<Eigen::Vector2d> pts{{1.01, 2.03}};
	const auto g = CCorrelationGrid::fromPoints(pts, res, sigma, 1.0);
	EXPECT_NEAR(g.probabilityAt(pts[0]), 1.0, 1e-12);
	const auto expected = [&](int dx, int dy)
	{
		const double d2 = (dx * dx + dy * dy) * res * res;
		return std::exp(-d2 / (2 * sigma * sigma));
	};
	for (const int d : {1, 2, 4, 6})
	{
		EXPECT_NEAR(g.probabilityAt(cellCentre(g, pts[0], d, 0)), expected(d, 0), 0.5 / 255)
			<< "at distance " << d << " cells";
		EXPECT_NEAR(g.probabilityAt(cellCentre(g, pts[0], 0, -d)), expected(0, d), 0.5 / 255);
	}
	EXPECT_NEAR(g.probabilityAt(cellCentre(g, pts[0], 1, 1)), expected(1, 1), 0.5 / 255);
	EXPECT_NEAR(g.probabilityAt(cellCentre(g, pts[0], -3, 2)), expected(3, 2), 0.5 / 255);
	// Outside the grid and far from the point.
	EXPECT_EQ(g.probabilityAt({-100, 0}), 0.0);
	EXPECT_EQ(g.probabilityAt(cellCentre(g, pts[0], 18, 0)), 0.0);
}

TEST(CorrelationGrid, OverlappingBlursTakeTheMaxNotTheSum)
{
	// A densely sampled wall has the same peak value and profile as a single point.
	std::vector<Eigen::Vector2d> pts;
	for (int k = 0; k < 200; ++k) pts.emplace_back(0.0101 + 0.0002 * (k % 10), 0.05 * (k / 10));
	const auto g = CCorrelationGrid::fromPoints(pts, 0.05, 0.1, 0.5);
	EXPECT_NEAR(g.probabilityAt(cellCentre(g, pts[100], 0, 0)), 1.0, 1e-12);
	EXPECT_NEAR(g.probabilityAt(cellCentre(g, pts[100], 2, 0)), std::exp(-0.5), 0.5 / 255);
	EXPECT_NEAR(g.probabilityAt(cellCentre(g, pts[100], -2, 0)), std::exp(-0.5), 0.5 / 255);
}

TEST(CorrelationGrid, PyramidLevelIsMaxOverBlockIncludingNegativeCells)
{
	std::mt19937 rng(3);
	std::uniform_real_distribution<double> u(0, 2.0);
	std::vector<Eigen::Vector2d> pts;
	for (int k = 0; k < 15; ++k) pts.emplace_back(u(rng), u(rng));
	const auto g = CCorrelationGrid::fromPoints(pts, 0.05, 0.07, 0.2, 5);
	ASSERT_EQ(g.numLevels(), 5);
	for (int h = 1; h < g.numLevels(); ++h)
	{
		const int w = 1 << h;
		for (int y = -w - 1; y <= g.height() + 1; ++y)
			for (int x = -w - 1; x <= g.width() + 1; ++x)
			{
				uint8_t m = 0;
				for (int b = 0; b < w; ++b)
					for (int a = 0; a < w; ++a) m = std::max(m, g.value(0, x + a, y + b));
				ASSERT_EQ(g.value(h, x, y), m) << "level " << h << " cell " << x << "," << y;
			}
	}
}

// Level 0 against its definition, round(255 exp(-min_j d2_ij res^2 / (2 sigma^2))) over the
// occupied cells j, for sparse points with a small blur (the disc-stamping path) and dense
// points with a wide one (the distance-transform path): both must give the same values.
TEST(CorrelationGrid, LevelZeroMatchesBruteForceForSparseAndDenseInput)
{
	std::mt19937 rng(7);
	for (const auto& [count, sigma] : {std::pair{12, 0.08}, std::pair{400, 0.6}})
	{
		std::uniform_real_distribution<double> u(0, 3.0);
		std::vector<Eigen::Vector2d> pts;
		for (int k = 0; k < count; ++k) pts.emplace_back(u(rng), u(rng));
		const double res = 0.05;
		const auto g = CCorrelationGrid::fromPoints(pts, res, sigma, 0.3, 3);
		std::vector<Eigen::Vector2i> occ;
		for (const auto& p : pts) occ.push_back(g.cellOf(p));
		for (int y = 0; y < g.height(); ++y)
			for (int x = 0; x < g.width(); ++x)
			{
				long d2 = std::numeric_limits<long>::max();
				for (const auto& o : occ)
					d2 = std::min(
						d2, long(o.x() - x) * (o.x() - x) + long(o.y() - y) * (o.y() - y));
				const double p =
					255.0 * std::exp(-double(d2) * res * res / (2 * sigma * sigma));
				const long expected = p < 0.5 ? 0 : std::lround(p);
				ASSERT_EQ(long(g.value(0, x, y)), expected)
					<< count << " points, sigma " << sigma << ", cell " << x << "," << y;
			}
	}
}

TEST(CorrelationGrid, RejectsBadInput)
{
	const std::vector<Eigen::Vector2d> pts{{0, 0}};
	EXPECT_THROW(CCorrelationGrid::fromPoints({}, 0.05, 0.1, 1), std::exception);
	EXPECT_THROW(CCorrelationGrid::fromPoints(pts, 0, 0.1, 1), std::exception);
	EXPECT_THROW(CCorrelationGrid::fromPoints(pts, 0.05, -1, 1), std::exception);
	EXPECT_THROW(CCorrelationGrid::fromPoints(pts, 0.05, 0.1, 1, 0), std::exception);
	EXPECT_THROW(CCorrelationGrid::fromPoints({{0, 0}, {1e6, 0}}, 0.05, 0.1, 1),
				 std::exception);
	EXPECT_THROW(CCorrelationGrid::fromPoints({{0, 0}, {std::nan(""), 0}}, 0.05, 0.1, 1),
				 std::exception);
}
