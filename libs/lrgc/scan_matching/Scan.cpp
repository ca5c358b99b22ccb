#include <lrgc/scan_matching/Scan.h>
#include <lrgc/scan_matching/FreeSpace.h>
#include <lrgc/scan_matching/RangeDenoiser.h>

#include <algorithm>
#include <cmath>

namespace lrgc
{
mrpt::obs::CObservation2DRangeScan::Ptr applyRangeLimits(
	const mrpt::obs::CObservation2DRangeScan::Ptr& obs, const TRangeLimits& limits,
	size_t* marked)
{
	ASSERT_(obs);
	const auto outside = [&](size_t i)
	{
		const double r = obs->getScanRange(i);
		return obs->getScanRangeValidity(i) &&
			   (r < limits.min || (limits.max > 0 && r > limits.max));
	};
	const size_t n = obs->getScanSize();
	size_t count = 0;
	for (size_t i = 0; i < n; ++i) count += outside(i) ? 1 : 0;
	if (marked) *marked = count;
	if (count == 0) return obs;
	auto out = std::make_shared<mrpt::obs::CObservation2DRangeScan>(*obs);
	for (size_t i = 0; i < n; ++i)
		if (outside(i)) out->setScanRangeValidity(i, false);
	return out;
}

const TBeamDirections& beamDirections(const mrpt::obs::CObservation2DRangeScan& obs)
{
	// One geometry per thread: a log's laser (two lasers alternating recompute each time,
	// as every scan did before).
	thread_local TBeamDirections beams;
	const size_t n = obs.getScanSize();
	if (beams.n == n && beams.aperture == obs.aperture && beams.rightToLeft == obs.rightToLeft)
		return beams;
	beams.n = n, beams.aperture = obs.aperture, beams.rightToLeft = obs.rightToLeft;
	beams.angle.resize(n), beams.cos.resize(n), beams.sin.resize(n);
	for (size_t i = 0; i < n; ++i)
	{
		const double a = obs.getScanAngle(i);
		beams.angle[i] = a, beams.cos[i] = std::cos(a), beams.sin[i] = std::sin(a);
	}
	return beams;
}

namespace
{
/** Counts reading i (range `r`) in `st` if it is not a return; true if it is one (kept as a
 * point). */
bool isReturn(const mrpt::obs::CObservation2DRangeScan& obs, size_t i, double r,
			  TScanConversionStats& st)
{
	if (!obs.getScanRangeValidity(i))
	{
		++st.invalidFlag;
		return false;
	}
	if (!std::isfinite(r))
	{
		++st.notFinite;
		return false;
	}
	if (r <= 0)
	{
		++st.nonPositive;
		return false;
	}
	if (r >= obs.maxRange)
	{
		++st.noReturn;
		return false;
	}
	return true;
}

/** Fraction of the sweep at beam i of n, from the middle beam: -1/2 (first) .. +1/2 (last). */
double sweepFraction(size_t i, size_t n)
{
	return n > 1 ? double(i) / double(n - 1) - 0.5 : 0.0;
}
}  // namespace

std::vector<float> sweepFractions(const mrpt::obs::CObservation2DRangeScan& obs)
{
	std::vector<float> out;
	TScanConversionStats st;
	const size_t n = obs.getScanSize();
	for (size_t i = 0; i < n; ++i)
		if (isReturn(obs, i, obs.getScanRange(i), st))
			out.push_back(float(sweepFraction(i, n)));
	return out;
}

size_t denoisedMatchStride(size_t window)
{
	return std::clamp<size_t>((window - std::min<size_t>(window, 1)) / 2, 1,
							  kMaxDenoisedMatchStride);
}

TScan2D scanFromObservation(const mrpt::obs::CObservation2DRangeScan& obs,
							TScanConversionStats* stats, const mrpt::math::TPose2D& sweepMotion,
							double rangeNoise)
{
	TScan2D scan;
	scan.maxRange = obs.maxRange;
	scan.timestamp = obs.timestamp;
	TScanConversionStats st;
	const size_t n = obs.getScanSize();
	st.total = n;
	scan.points.reserve(n);

	// Sensor pose on the robot, projected onto the ground plane (x, y, yaw).
	const double sx = obs.sensorPose.x(), sy = obs.sensorPose.y();
	const double sc = std::cos(obs.sensorPose.yaw()), ss = std::sin(obs.sensorPose.yaw());
	const bool deskew = sweepMotion.x != 0 || sweepMotion.y != 0 || sweepMotion.phi != 0;
	// Ranges as measured, or denoised where the laser's noise is large (RangeDenoiser.h):
	// only then is a copy made.
	std::vector<float> denoised;
	if (rangeNoise > kNoisyLaserStd_m)
	{
		size_t window = 1;
		denoised = denoisedRanges(obs, rangeNoise, &window);
		scan.rangeNoiseStd = rangeNoise / std::sqrt(double(window));
		scan.matchStride = denoisedMatchStride(window);
	}
	// Beam angles in the sensor frame [rad]: -aperture/2 .. +aperture/2 (rightToLeft).
	const TBeamDirections& beams = beamDirections(obs);
	for (size_t i = 0; i < n; ++i)
	{
		const double measured = obs.getScanRange(i);
		if (!isReturn(obs, i, measured, st)) continue;
		const double r = denoised.empty() ? measured : denoised[i];
		const double px = r * beams.cos[i], py = r * beams.sin[i];
		const double rx = sx + sc * px - ss * py, ry = sy + ss * px + sc * py;
		if (!deskew)
		{
			scan.points.emplace_back(rx, ry);
			continue;
		}
		// De-skew (file comment of Scan.h): into the robot frame at the middle beam's time.
		const double f = sweepFraction(i, n);
		const double fc = std::cos(f * sweepMotion.phi), fs = std::sin(f * sweepMotion.phi);
		scan.points.emplace_back(fc * rx - fs * ry + f * sweepMotion.x,
								 fs * rx + fc * ry + f * sweepMotion.y);
	}
	if (stats) *stats = st;
	scan.rangeImage = std::make_shared<const CRangeImage>(scan.points);
	return scan;
}

}  // namespace lrgc
