#include <gtest/gtest.h>

#include <lrgc/common/se2.h>

#include <random>

using lrgc::TPose2D;

TEST(SE2, ComposeInverseIsIdentityIncludingAngleWrap)
{
	std::mt19937 rng(42);
	std::uniform_real_distribution<double> u(-10, 10), a(-M_PI, M_PI);
	for (int i = 0; i < 200; ++i)
	{
		const TPose2D p{u(rng), u(rng), a(rng)};
		const TPose2D e = lrgc::compose(p, lrgc::inverse(p));
		EXPECT_NEAR(e.x, 0, 1e-12);
		EXPECT_NEAR(e.y, 0, 1e-12);
		EXPECT_NEAR(e.phi, 0, 1e-12);
	}
	// Angles just either side of +-pi compose across the wrap.
	const TPose2D a1{0, 0, M_PI - 0.01}, a2{0, 0, 0.02};
	EXPECT_NEAR(lrgc::compose(a1, a2).phi, -M_PI + 0.01, 1e-12);
}

TEST(SE2, BetweenMatchesMrptOperatorMinus)
{
	std::mt19937 rng(7);
	std::uniform_real_distribution<double> u(-5, 5), a(-M_PI, M_PI);
	for (int i = 0; i < 200; ++i)
	{
		const TPose2D p{u(rng), u(rng), a(rng)}, q{u(rng), u(rng), a(rng)};
		const TPose2D mine = lrgc::between(p, q), mrpts = q - p;
		EXPECT_NEAR(mine.x, mrpts.x, 1e-9);
		EXPECT_NEAR(mine.y, mrpts.y, 1e-9);
		EXPECT_NEAR(mrpt::math::wrapToPi(mine.phi - mrpts.phi), 0, 1e-9);
		const TPose2D back = lrgc::compose(p, mine);
		EXPECT_NEAR(back.x, q.x, 1e-9);
		EXPECT_NEAR(back.y, q.y, 1e-9);
	}
}
