/* CScanMatcher on real data: consecutive scans of Debian's SENA one-loop rawlog (224 scans,
 * 361 beams), odometry increments from CActionRobotMovement2D as guesses. There is no ground
 * truth here: the test checks the match rate, that the matcher's corrections to odometry are
 * plausible, and that every covariance is positive definite; it prints typical figures. */
#include <gtest/gtest.h>
#include <lrgc/scan_matching/ScanMatcher.h>
#include <lrgc/common/se2.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/serialization/CArchive.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <iostream>

#include "test_data.h"

using namespace lrgc;
using mrpt::math::TPose2D;

TEST(ScanMatcherRealData, senaConsecutiveScans)
{
	const std::string path = lrgc::test::senaRawlogPath();
	LRGC_SKIP_IF_MISSING(path);
	mrpt::io::CFileGZInputStream f(path);
	auto arch = mrpt::serialization::archiveFrom(f);
	mrpt::obs::CActionCollection::Ptr acts;
	mrpt::obs::CSensoryFrame::Ptr sf;
	mrpt::obs::CObservation::Ptr obs;
	size_t entry = 0;
	std::vector<TScan2D> scans;
	std::vector<TPose2D> odoSincePrev;  // odometry from the previous scan to this one
	TPose2D pending(0, 0, 0);
	while (
		mrpt::obs::CRawlog::getActionObservationPairOrObservation(arch, acts, sf, obs, entry))
	{
		if (acts)
			if (auto mv = acts->getBestMovementEstimation(); mv && mv->poseChange)
				pending = compose(pending, mv->poseChange->getMeanVal().asTPose());
		if (!sf) continue;
		if (auto s = sf->getObservationByClass<mrpt::obs::CObservation2DRangeScan>())
		{
			scans.push_back(scanFromObservation(*s));
			odoSincePrev.push_back(pending);
			pending = TPose2D(0, 0, 0);
		}
	}
	ASSERT_GT(scans.size(), 200U);

	const TScanMatcherParams params;
	const CScanMatcher matcher(params);
	int matched = 0, pairs = 0;
	std::vector<double> sdX, sdPhi, corr, rms;
	for (size_t k = 1; k < scans.size(); ++k)
	{
		++pairs;
		const auto ref = CReferenceCloud::fromScan(scans[k - 1], params);
		const auto m = matcher.match(ref, scans[k], odoSincePrev[k]);
		if (!m) continue;
		++matched;
		const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(m->cov);
		EXPECT_GT(es.eigenvalues().minCoeff(), 0) << "scan " << k;
		sdX.push_back(std::sqrt(std::max(m->cov(0, 0), m->cov(1, 1))));
		sdPhi.push_back(std::sqrt(m->cov(2, 2)));
		corr.push_back(translationNorm(between(odoSincePrev[k], m->scanInRef)));
		rms.push_back(m->rmsResidual);
	}
	auto med = [](std::vector<double> v)
	{
		std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
		return v[v.size() / 2];
	};
	auto q95 = [](std::vector<double> v)
	{
		std::sort(v.begin(), v.end());
		return v[static_cast<size_t>(0.95 * (v.size() - 1))];
	};
	std::cout << "SENA consecutive scans: matched " << matched << "/" << pairs
			  << "; median sd(xy) " << med(sdX) * 1000 << " mm (95% " << q95(sdX) * 1000
			  << "), median sd(phi) " << med(sdPhi) * 180 / M_PI
			  << " deg, median correction to odometry " << med(corr) * 1000 << " mm (95% "
			  << q95(corr) * 1000 << "), median rms residual " << med(rms) * 1000 << " mm\n";
	EXPECT_GE(matched, 0.9 * pairs);
	EXPECT_LT(q95(corr), 0.3);  // odometry between consecutive scans is off by centimetres
	EXPECT_LT(med(sdX), 0.02);
}
