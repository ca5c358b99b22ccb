/* TScan2D: a 2D range scan as the LRGC stages use it.
 *
 * Only the valid returns are kept, as points in the robot (base) frame, i.e. the sensor pose
 * on the robot is already applied: p_robot = sensorInRobot (+) (r cos(a), r sin(a)).
 *
 * De-skewing: a rotating-mirror laser fires its beams one after the other (SICK LMS 2xx: the
 * 180 deg of a scan in 6.7 ms, first beam first), so a scan taken while turning at w rad/s is
 * stretched (w > 0, beams sweeping the same way) or squeezed in angle by w * sweep. Matched
 * against each other, two such scans under-estimate a counter-clockwise turn and over-estimate
 * a clockwise one, both by |dphi| * |w| * sweep / pi: a clockwise heading drift at every turn,
 * whichever way the robot turns. Local registration alone drifts clockwise on all three
 * benchmark logs (Intel -5, ACES -13, MIT-CSAIL -7 deg over the log, against the loop-closed
 * trajectory). Given the robot's motion over the sweep (first beam -> last beam, robot frame),
 * each point is moved into the robot frame at the middle beam's time, with the fraction
 * f = i / (n - 1) - 1/2 of that motion at its beam i:  p = R(f dphi) p_i + f (dx, dy).
 * The sweep time is a property of the laser set-up ([MapBuilder] scan_sweep_time_s, 0 = off by
 * default); scripts/calibrate-sweep-time finds it from a log with loops, without ground truth
 * (Intel and MIT-CSAIL: 4.5 ms, ACES: 26.7 ms).
 * No-return readings (invalid flag, NaN, r <= 0, r >= maxRange) are not obstacles and are
 * dropped here; the count of each kind is reported so callers can say what they skipped.
 * Range limits ([MapBuilder] min_range_m, max_range_m: a robot's own posts, a 360-degree
 * lidar's view of the robot) are applied before, to the observation itself (applyRangeLimits),
 * so that the occupancy grid and the saved keyframes drop those readings too.
 */
#pragma once

#include <mrpt/core/Clock.h>
#include <mrpt/math/TPose2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <Eigen/Core>
#include <cstddef>
#include <memory>
#include <vector>

namespace lrgc
{
class CRangeImage;

struct TScan2D
{
	/** Valid returns in the robot frame [m]. */
	std::vector<Eigen::Vector2d> points;
	/** Sensor range limit [m]; readings at or above it were no-returns. */
	double maxRange = 0;
	mrpt::Clock::time_point timestamp{};
	/** Range noise std left in the points of a noisy laser's scan [m]: the laser's estimate
	 * divided by sqrt(2h+1), the denoiser's window (RangeDenoiser.h); 0 for a laser below
	 * kNoisyLaserStd_m (the gates as configured). */
	double rangeNoiseStd = 0;
	/** A scan match pairs every matchStride-th point (CScanMatcher::match): 1 but for a
	 * denoised scan (denoisedMatchStride): its neighbouring returns come from windows of rays
	 * that are mostly the same, so their noise is mostly the same, and matching them all
	 * buys little precision for its cost. The free-space check and the reference clouds built
	 * from the scan use all the points. */
	size_t matchStride = 1;
	/** The free-space check's range image of `points` (CRangeImage, FreeSpace.h), built once
	 * by scanFromObservation and shared by the copies, so that neither each check nor each
	 * window patch holding the scan bins its points again; null: built where needed
	 * (rangeImageOf). Whoever changes `points` resets it. */
	std::shared_ptr<const CRangeImage> rangeImage;
};

/** Why readings of a scan were dropped. */
struct TScanConversionStats
{
	size_t total = 0;        //!< rays in the observation
	size_t invalidFlag = 0;  //!< marked invalid by the driver / reader
	size_t notFinite = 0;    //!< NaN or infinite range
	size_t nonPositive = 0;  //!< r <= 0
	size_t noReturn = 0;     //!< r >= maxRange
	size_t kept() const { return total - invalidFlag - notFinite - nonPositive - noReturn; }
};

/** Range limits of a laser [m]; 0 = no limit. */
struct TRangeLimits
{
	double min = 0;  //!< [m] readings below are dropped (the robot's own posts, ...); 0: none
	double max = 0;  //!< [m] readings above are dropped; 0: only the sensor's own maxRange
	bool active() const { return min > 0 || max > 0; }
};

/** `obs` with its valid readings r < limits.min or r > limits.max marked invalid, the way
 * MRPT's own filters mark excluded readings (CObservation2DRangeScan::filterByExclusionAreas):
 * the scan conversion then drops them, and MRPT's grid insertion treats them as no-returns.
 * A modified copy if a reading is marked, `obs` itself otherwise (never changed). `*marked`,
 * if given, receives the number of readings marked. */
mrpt::obs::CObservation2DRangeScan::Ptr applyRangeLimits(
	const mrpt::obs::CObservation2DRangeScan::Ptr& obs, const TRangeLimits& limits,
	size_t* marked = nullptr);

/** Largest TScan2D::matchStride [points]: MRPT's range_030_bearing_015.rawlog (361 beams,
 * 0.30 m Gaussian range noise, denoised over 41 rays) keeps 91 points a match, a point every 2
 * degrees; its ATE with strides 1 to 4 stays within the run-to-run spread (doc/architecture.md,
 * stop 50). */
constexpr size_t kMaxDenoisedMatchStride = 4;

/** The matchStride of a scan denoised over `window` = 2h+1 rays (RangeDenoiser.h; 1: as
 * measured): min(h, kMaxDenoisedMatchStride), at least 1. Returns k rays apart share
 * 2h+1-k of their window's rays: at k <= h more than half. */
size_t denoisedMatchStride(size_t window);

/** Converts an MRPT laser observation; never throws on bad ranges (they are counted).
 * `rangeNoise`: the laser's range noise std [m] (CRangeNoiseEstimate); above
 * kNoisyLaserStd_m the ranges are denoised first (RangeDenoiser.h) and the scan's
 * rangeNoiseStd says what is left; 0: ranges as measured, rangeNoiseStd 0.
 * `sweepMotion`: the robot's motion over the sweep, first beam -> last beam, in the robot
 * frame [m, m, rad] (zero: no de-skewing). */
TScan2D scanFromObservation(const mrpt::obs::CObservation2DRangeScan& obs,
							TScanConversionStats* stats = nullptr,
							const mrpt::math::TPose2D& sweepMotion = mrpt::math::TPose2D(0, 0,
																						 0),
							double rangeNoise = 0);

/** Each beam's bearing a_i [rad, sensor frame] (CObservation2DRangeScan::getScanAngle(i)) with
 * cos a_i and sin a_i. They depend on the scan's geometry alone (beam count, aperture,
 * direction: all getScanAngle reads), the same for every scan of a laser, so beamDirections
 * computes them once per geometry and thread: the denoiser and the conversion took 3 sines
 * and cosines per beam of every scan (0.25 G instructions of range_030_bearing_015's whole run,
 * a 361-beam noisy laser). The same values as computed at each use, bit for bit. */
struct TBeamDirections
{
	size_t n = 0;
	float aperture = 0;
	bool rightToLeft = true;
	std::vector<double> angle, cos, sin;
};

/** obs's beam directions (above); the reference is valid until the calling thread asks for
 * another geometry's. */
const TBeamDirections& beamDirections(const mrpt::obs::CObservation2DRangeScan& obs);

/** The sweep fraction f = i / (n - 1) - 1/2 of each point scanFromObservation(obs) keeps, in
 * the same order: where in the sweep (first beam -1/2, last +1/2) the point was measured. */
std::vector<float> sweepFractions(const mrpt::obs::CObservation2DRangeScan& obs);

}  // namespace lrgc
