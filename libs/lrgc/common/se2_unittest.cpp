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

// agreesWhateverTheOtherCovariance proves agreement for any positive semidefinite B only where
// the test with B agrees (random A, B, poses); and it proves nothing for a singular A.
TEST(SE2, AgreementProvenWithoutTheOtherCovarianceHoldsWithIt)
{
	std::mt19937 rng(7);
	std::uniform_real_distribution<double> u(-1, 1), small(-0.2, 0.2);
	const auto psd = [&](double scale)
	{
		Eigen::Matrix3d L;
		for (int r = 0; r < 3; ++r)
			for (int c = 0; c < 3; ++c) L(r, c) = scale * u(rng);
		return Eigen::Matrix3d(L * L.transpose());
	};
	int proven = 0;
	for (int i = 0; i < 2000; ++i)
	{
		const Eigen::Matrix3d A = psd(0.3) + 1e-3 * Eigen::Matrix3d::Identity();
		const Eigen::Matrix3d B = psd(0.3 * std::abs(u(rng)));
		const TPose2D e{u(rng), u(rng), u(rng)};
		const TPose2D m = lrgc::compose(e, TPose2D{small(rng), small(rng), small(rng)});
		if (!lrgc::agreesWhateverTheOtherCovariance(e, m, A, 7.81)) continue;
		++proven;
		EXPECT_LE(lrgc::disagreementChi2(e, m, A + B), 7.81);
	}
	EXPECT_GT(proven, 100);  // the bound decides a good share of these draws
	EXPECT_FALSE(lrgc::agreesWhateverTheOtherCovariance(TPose2D{0, 0, 0}, TPose2D{0, 0, 0},
														Eigen::Matrix3d::Zero(), 7.81));
}
