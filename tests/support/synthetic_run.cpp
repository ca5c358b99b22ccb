#include "synthetic_run.h"

#include <lrgc/common/se2.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>

#include <algorithm>
#include <cmath>

namespace lrgc::test
{
using mrpt::math::TPose2D;

mrpt::obs::CObservation2DRangeScan::Ptr laserObservationFromScan(const lrgc::TScan2D& scan,
																 const TLaserSimParams& laser,
																 mrpt::Clock::time_point t,
																 const std::string& label)
{
	auto obs = mrpt::obs::CObservation2DRangeScan::Create();
	obs->timestamp = t;
	obs->sensorLabel = label;
	obs->aperture = static_cast<float>(laser.fov_deg * M_PI / 180);
	obs->rightToLeft = true;
	obs->maxRange = static_cast<float>(laser.maxRange);
	obs->stdError = static_cast<float>(laser.rangeNoiseStd);
	const auto& s = laser.sensorInRobot;
	obs->sensorPose = mrpt::poses::CPose3D(s.x, s.y, 0, s.phi, 0, 0);
	obs->resizeScan(laser.beams);
	for (int i = 0; i < laser.beams; ++i)
	{
		obs->setScanRange(i, static_cast<float>(laser.maxRange));
		obs->setScanRangeValidity(i, false);
	}
	// simulateScan puts each return exactly on its beam: recover the beam index from the
	// bearing in the sensor frame, a = -fov/2 + fov * i / (beams - 1).
	const double fov = laser.fov_deg * M_PI / 180, step = fov / (laser.beams - 1);
	const TPose2D robotInSensor = lrgc::inverse(laser.sensorInRobot);
	for (const auto& pRobot : scan.points)
	{
		const Eigen::Vector2d p = lrgc::transformPoint(robotInSensor, pRobot);
		const long i = std::lround((std::atan2(p.y(), p.x()) + fov / 2) / step);
		ASSERT_(i >= 0 && i < laser.beams);
		obs->setScanRange(i, static_cast<float>(p.norm()));
		obs->setScanRangeValidity(i, true);
	}
	return obs;
}

mrpt::Clock::time_point syntheticStepTime(size_t k, double scanPeriod, double t0)
{
	return mrpt::Clock::fromDouble(t0 + scanPeriod * double(k));
}

void feedBuilder(lrgc::CMetricMapBuilderLRGC& builder, const CSyntheticWorld& world,
				 const TTrajectory& tr, const TSyntheticRunOptions& opt)
{
	ASSERT_EQUAL_(tr.odometryPoses.size(), tr.truePoses.size());
	std::mt19937 rng(opt.laserSeed);
	for (size_t k = 0; k < tr.truePoses.size(); ++k)
	{
		const auto t = syntheticStepTime(k, opt.scanPeriod, opt.firstStepTime);
		if (opt.odometry)
		{
			auto odo = mrpt::obs::CObservationOdometry::Create();
			odo->timestamp = t;
			odo->sensorLabel = "ODOMETRY";
			odo->odometry = mrpt::poses::CPose2D(tr.odometryPoses[k]);
			builder.processObservation(odo);
		}
		TLaserSimParams laser = opt.laser;
		laser.sensorInRobot = lrgc::compose(
			opt.laser.sensorInRobot,
			TPose2D(0, 0, opt.beamOffsetStep * double(k % std::max(1, opt.beamOffsetCycle))));
		const auto& p = tr.truePoses[k];
		const TScan2D scan =
			opt.crowd
				? simulateScan(opt.crowd->addTo(world, opt.scanPeriod * double(k), {p.x, p.y}),
							   p, laser, rng)
				: simulateScan(world, p, laser, rng);
		builder.processObservation(laserObservationFromScan(scan, laser, t));
	}
	if (opt.finish) builder.finish();
}

TTrajectoryError trajectoryError(const std::vector<TPose2D>& estimate,
								 const std::vector<TPose2D>& truth)
{
	ASSERT_EQUAL_(estimate.size(), truth.size());
	ASSERT_(!truth.empty());
	TTrajectoryError e;
	double sum2 = 0;
	for (size_t k = 0; k < truth.size(); ++k)
	{
		const TPose2D d = lrgc::between(truth[k], lrgc::compose(truth.front(), estimate[k]));
		const double dxy = lrgc::translationNorm(d);
		sum2 += dxy * dxy;
		if (dxy > e.maxXY) e.maxXY = dxy, e.worstIndex = k;
		e.maxPhi = std::max(e.maxPhi, std::abs(d.phi));
		e.finalXY = dxy;
	}
	e.rmsXY = std::sqrt(sum2 / double(truth.size()));
	return e;
}

TTrajectoryError trajectoryError(const lrgc::TTrajectory& estimate,
								 const std::vector<TPose2D>& truth)
{
	std::vector<TPose2D> poses;
	for (const auto& s : estimate) poses.push_back(s.robotInMap);
	return trajectoryError(poses, truth);
}

std::vector<TPose2D> trueKeyframePoses(const lrgc::CMetricMapBuilderLRGC& builder,
									   const std::vector<TPose2D>& truth)
{
	std::vector<TPose2D> out;
	for (const auto& kf : builder.keyframes())
	{
		ASSERT_(kf.scanIndex < truth.size());
		out.push_back(lrgc::between(truth.front(), truth[kf.scanIndex]));
	}
	return out;
}

TLoopLinkAudit auditLoopLinks(const lrgc::CMetricMapBuilderLRGC& builder,
							  const std::vector<TPose2D>& truth, double maxXY, double maxPhi)
{
	const auto kfTruth = trueKeyframePoses(builder, truth);
	const auto& g = builder.graph();
	TLoopLinkAudit a;
	for (size_t id = 0; id < g.numLinks(); ++id)
	{
		const auto& l = g.link(id);
		if (l.type != lrgc::LinkType::LoopClosure) continue;
		const TPose2D d =
			lrgc::between(lrgc::between(kfTruth[l.from], kfTruth[l.to]), l.toInFrom);
		const double dxy = lrgc::translationNorm(d), dphi = std::abs(d.phi);
		const Eigen::Vector3d e = lrgc::toVector(d);
		const double chi2 = e.dot(l.information * e);
		const bool ok = (dxy <= maxXY && dphi <= maxPhi) || chi2 <= 16.27;
		if (!g.isLinkEnabled(id))
		{
			++(ok ? a.disabledTrue : a.disabledFalse);
			continue;
		}
		++(ok ? a.enabledTrue : a.enabledFalse);
		if (ok) a.enabledTrueLinks.emplace_back(l.from, l.to);
		a.worstEnabledXY = std::max(a.worstEnabledXY, dxy);
		a.worstEnabledPhi = std::max(a.worstEnabledPhi, dphi);
		a.worstEnabledChi2 = std::max(a.worstEnabledChi2, chi2);
		if (!ok && a.firstEnabledFalse.empty())
			a.firstEnabledFalse =
				mrpt::format("%zu -> %zu: %.2f m, %.1f deg off the truth, chi2 %.1f", l.from,
							 l.to, dxy, dphi * 180 / M_PI, chi2);
	}
	return a;
}

void rebuildOdometryPoses(TTrajectory& tr)
{
	tr.odometryPoses.resize(1);
	for (const auto& inc : tr.odometryIncrements)
		tr.odometryPoses.push_back(lrgc::compose(tr.odometryPoses.back(), inc));
}

void scaleOdometry(TTrajectory& tr, double turnScale, double travelScale)
{
	for (size_t i = 0; i < tr.odometryIncrements.size(); ++i)
	{
		const mrpt::math::TPose2D step = lrgc::between(tr.truePoses[i], tr.truePoses[i + 1]);
		tr.odometryIncrements[i].phi += (turnScale - 1) * step.phi;
		tr.odometryIncrements[i].x += (travelScale - 1) * step.x;
		tr.odometryIncrements[i].y += (travelScale - 1) * step.y;
	}
	rebuildOdometryPoses(tr);
}

TSyntheticRunOptions longRangeSick(double scanPeriod, double maxRange, double maxRangeDropRate,
								   uint32_t laserSeed)
{
	TSyntheticRunOptions opt;
	opt.scanPeriod = scanPeriod;
	opt.laser.beams = 181;
	opt.laser.maxRange = maxRange;
	opt.laser.rangeNoiseStd = 0.01;
	opt.laser.dropRate = 0.02;
	opt.laser.outlierRate = 0.005;
	opt.laser.maxRangeDropRate = maxRangeDropRate;
	opt.laser.mixedPixelRate = 1;
	opt.beamOffsetStep = mrpt::DEG2RAD(0.25);
	opt.beamOffsetCycle = 4;
	opt.laserSeed = laserSeed;
	return opt;
}

CSyntheticWorld makeRingCorridorWorld(double W, double H, double w, uint32_t seed, int boxes)
{
	ASSERT_(W > 2 * w && H > 2 * w && w > 0.6);
	CSyntheticWorld world;
	world.addPolygon({{0, 0}, {W, 0}, {W, H}, {0, H}});
	world.addPolygon({{w, w}, {W - w, w}, {W - w, H - w}, {w, H - w}});
	std::mt19937 rng(seed);
	std::uniform_real_distribution<double> u(0, 1);
	for (int i = 0; i < boxes; ++i)
	{
		const int side = std::min(3, int(u(rng) * 4));
		const double s = u(rng), h = 0.15;
		const Eigen::Vector2d c = side == 0   ? Eigen::Vector2d(w + s * (W - 2 * w), h)
								  : side == 1 ? Eigen::Vector2d(W - h, w + s * (H - 2 * w))
								  : side == 2 ? Eigen::Vector2d(w + s * (W - 2 * w), H - h)
											  : Eigen::Vector2d(h, w + s * (H - 2 * w));
		world.addBox(c, h, h);
	}
	return world;
}

double minClearance(const CSyntheticWorld& world, const std::vector<TPose2D>& poses)
{
	double best = 1e18;
	for (size_t k = 0; k < poses.size(); ++k)
	{
		const Eigen::Vector2d a(poses[k].x, poses[k].y);
		const Eigen::Vector2d b =
			k + 1 < poses.size() ? Eigen::Vector2d(poses[k + 1].x, poses[k + 1].y) : a;
		for (int s = 0; s <= 4; ++s)
			best = std::min(best, world.distanceToNearest(a + (b - a) * (s / 4.0)));
	}
	return best;
}

}  // namespace lrgc::test
