/* Range noise of a laser scan, estimated from the scan itself, and an edge-preserving
 * denoiser for lasers whose noise is large against the matcher's scales.
 *
 * Noise: along a smooth surface, consecutive ranges are locally linear in the beam index, so
 * the second difference d_i = r_{i-1} - 2 r_i + r_{i+1} of three valid returns is noise alone,
 * with variance 6 sigma^2 for independent range noise of std sigma. Triples with a step of 1 m
 * or more between neighbours are edges, not noise (GlassBuilding's panes alternate near and
 * far returns), and are left out. The estimate is
 *     sigma = q25_i |d_i| / (0.31864 sqrt(6))     [m]
 * (the lower quartile of |d|, 0.31864 sqrt(6) sigma for Gaussian noise: corners, edges and
 * clutter, the upper part, do not move it; the median let Intel's open lab, desks and chairs
 * at every degree, read up to 0.6 m). A log's estimate is the median over its recent scans
 * (CRangeNoiseEstimate). MRPT's simulator with range noise 0.30 m gives 0.32 m.
 *
 * Denoising (only when sigma exceeds kNoisyLaserStd_m): each return i is moved along its own
 * ray onto a line fitted to its neighbours, in the sensor frame. The noise lies along the
 * rays, so the line is fitted in ray space: a line n . p = d meets the ray of bearing a at
 * 1 / r(a) = A cos(a) + B sin(a), (A, B) = n / d, linear least squares in (A, B) over 1 / r_i
 * (a total-least-squares fit of the points takes the noise as isotropic and, where a window
 * spans less along the wall than the noise across it, a 5 m corridor's side walls, fits the
 * noise's direction). The window centred on i, [i-h, i+h], is used if its residual is what one
 * line with noise sigma gives; else (a corner) the better of the left [i-2h, i] and right
 * [i, i+2h] windows if it is one line (at a corner one side lies on a single wall); else (a
 * far wall narrower than the window, whose corners the fit would cut) half the window is
 * tried, down to 3 returns. A one-sided window extrapolates to its end, with twice the error
 * of the centred one. The fitted range at the window centre has variance sigma^2 / (2h+1), so h
 * = ceil(((sigma / kDenoiseTargetStd_m)^2 - 1) / 2), at most kDenoiseMaxHalfWindow. A return is
 * kept as measured if its ray grazes the line (|cos| < 0.2) or the line is more than 3 sigma
 * away along the ray (a return off any wall: a post, a person).
 */
#pragma once

#include <mrpt/obs/CObservation2DRangeScan.h>

#include <deque>
#include <vector>

namespace lrgc
{
/** sigma above [m], from the scan's valid returns; 0 with fewer than 10 valid triples. */
double rangeNoiseStd(const mrpt::obs::CObservation2DRangeScan& obs);

/** The laser's range noise [m]: the median of the per-scan estimates (rangeNoiseStd) of the
 * last kWindow scans. One scan's estimate is not the laser's: on Intel it is 6 mm for the
 * median scan and 0.34 m for the 99th percentile (scans mostly of clutter or no-returns). */
class CRangeNoiseEstimate
{
public:
	static constexpr size_t kWindow = 101;
	/** Adds a scan's estimate (0: none, ignored); returns the current median (0 before any). */
	double add(double scanSigma);

private:
	std::deque<double> m_recent;
};

/** Range noise [m] above which a laser is noisy: its scans are denoised and the matcher's and
 * correlator's gates widen with what noise is left (TScan2D::rangeNoiseStd). The shared logs'
 * lasers estimate at most 0.026 m (Intel, MIT-CSAIL) and 0.064 m (ACES, Killian: ranges in
 * 5 cm steps, whose second differences are multiples of 5 cm); MRPT's simul.rawlog 0.07 m
 * (its simulator ray-casts a 5 cm grid); range_030_bearing_015.rawlog 0.32 m. */
constexpr double kNoisyLaserStd_m = 0.1;
/** Target std of the denoised ranges [m]. */
constexpr double kDenoiseTargetStd_m = 0.05;
/** Largest half-window [rays]: 25 rays of 0.5 deg span 12.5 deg. */
constexpr int kDenoiseMaxHalfWindow = 25;

/** Ranges of `obs` (one per ray; invalid rays keep their value), denoised as above for range
 * noise `sigma` [m] down to kDenoiseTargetStd_m if sigma > kNoisyLaserStd_m; `*window`
 * receives the window 2h+1 (1: the ranges as measured). */
std::vector<float> denoisedRanges(const mrpt::obs::CObservation2DRangeScan& obs, double sigma,
								  size_t* window);

}  // namespace lrgc
