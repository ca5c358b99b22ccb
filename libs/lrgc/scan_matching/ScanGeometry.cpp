#include <lrgc/scan_matching/ScanGeometry.h>

#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>

#include <algorithm>
#include <cmath>

namespace lrgc
{
namespace
{
// Why the scan's geometry cannot place its rays, or empty if it can.
std::string geometryProblem(const mrpt::obs::CObservation2DRangeScan& obs)
{
	// One ray has no angular step (aperture / (n - 1)): its angle, hence its point, is NaN.
	if (obs.getScanSize() < 2)
		return mrpt::format("%zu ray(s): fewer than 2", obs.getScanSize());
	if (!std::isfinite(obs.aperture) || !(obs.aperture > 0) ||
		obs.aperture > 2 * M_PI * (1 + 1e-9))
		return mrpt::format("aperture = %g rad (must be in (0, 2 pi])", obs.aperture);
	const auto& p = obs.sensorPose;
	for (const double v : {p.x(), p.y(), p.z(), p.yaw(), p.pitch(), p.roll()})
		if (!std::isfinite(v))
			return "sensorPose has a non-finite value (" + p.asString() + ")";
	if (std::abs(p.x()) > kMaxSensorOffset || std::abs(p.y()) > kMaxSensorOffset ||
		std::abs(p.z()) > kMaxSensorOffset)
		return mrpt::format("sensorPose (%s) is more than %g m from the robot",
							p.asString().c_str(), kMaxSensorOffset);
	if (!std::isfinite(obs.maxRange) || !(obs.maxRange > 0))
		return mrpt::format("maxRange = %g m (no reading can be a return)", obs.maxRange);
	return {};
}

bool beyondMaxRange(const mrpt::obs::CObservation2DRangeScan& obs, size_t i)
{
	const double r = obs.getScanRange(i);
	return obs.getScanRangeValidity(i) && std::isfinite(r) && r > kMaxRange;
}
}  // namespace

TScanGeometryCheck checkScanGeometry(const mrpt::obs::CObservation2DRangeScan::Ptr& obs)
{
	ASSERT_(obs);
	TScanGeometryCheck out;
	out.problem = geometryProblem(*obs);
	if (!out.problem.empty()) return out;
	const size_t n = obs->getScanSize();
	for (size_t i = 0; i < n; ++i) out.clipped += beyondMaxRange(*obs, i) ? 1 : 0;
	if (out.clipped == 0 && obs->maxRange <= kMaxRange)
	{
		out.scan = obs;
		return out;
	}
	out.scan = std::make_shared<mrpt::obs::CObservation2DRangeScan>(*obs);
	out.scan->maxRange = static_cast<float>(std::min<double>(obs->maxRange, kMaxRange));
	for (size_t i = 0; i < n; ++i)
		if (beyondMaxRange(*obs, i)) out.scan->setScanRangeValidity(i, false);
	return out;
}

}  // namespace lrgc
