/* Information of a scan-match link in the graph.
 *
 * The matcher's covariance is honest for the noise it models (NEES ~3 on synthetic scenes),
 * but real scans add errors it cannot see from one pair: surfaces sampled differently from two
 * poses, beam width, motion during the sweep, timing. A floor (added covariance) keeps a
 * link from claiming sub-millimetre precision. And when one scan takes part in `share` links
 * of the same window, its information is split among them (conservative fusion), so the
 * window does not count the same measurement `share` times:
 *     Omega = ( C_match + diag(fxy^2, fxy^2, fphi^2) )^-1 / share
 */
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>

#include <algorithm>
#include <string>

namespace mrpt::config
{
class CConfigFileBase;
}

namespace lrgc
{
struct TLinkNoise
{
	double floor_xy_m = 0.01;              //!< [m]
	double floor_phi = 0.25 * M_PI / 180;  //!< [rad] (0.25 deg)

	/** diag(fxy^2, fxy^2, fphi^2): the covariance the floor adds [m^2, m^2, rad^2]. */
	Eigen::Matrix3d floorCovariance() const
	{
		const Eigen::Vector3d floor2(floor_xy_m * floor_xy_m, floor_xy_m * floor_xy_m,
									 floor_phi * floor_phi);
		return floor2.asDiagonal();
	}

	/** Keys <prefix>link_floor_xy_m [m] and <prefix>link_floor_phi_deg of section s (each
	 * must be >= 0); missing keys keep the current values. */
	void load(const mrpt::config::CConfigFileBase& c, const std::string& s,
			  const std::string& prefix);
	/** The same keys, commented "Std added to <what>". */
	void save(mrpt::config::CConfigFileBase& c, const std::string& s, const std::string& prefix,
			  const std::string& what) const;
};

/** The floor of a loop link whose scan was denoised (RangeDenoiser.h), leftNoiseStd [m] the
 * range noise left in it (TScan2D::rangeNoiseStd, sigma / sqrt(2h+1); 0: ranges as measured,
 * `noise` as it is). The rays of one window share a line fit, so a denoised wall is off as a
 * whole by about leftNoiseStd; the walls that pin a corridor's axis (a far wall narrower than
 * the window, a corner) are fitted over half a window or less, sqrt(2) leftNoiseStd or more;
 * and a loop link joins two scans seen from other distances, whose fits err apart (sqrt(2)
 * again):
 *     floor_xy_m >= 2 leftNoiseStd.
 * Scans of one window see their walls from nearly the same place and their fits err alike, so
 * the window's links keep the matcher's covariance. On the noisy ring (0.3 m range noise, 5 m
 * corridors) the loop links' chi2 against the truth had a median of 5-10 (3 dof: 2.4), 1.4-2.5
 * with this floor. */
inline TLinkNoise denoisedLoopLinkNoise(TLinkNoise noise, double leftNoiseStd)
{
	noise.floor_xy_m = std::max(noise.floor_xy_m, 2 * leftNoiseStd);
	return noise;
}

inline Eigen::Matrix3d linkInformation(const Eigen::Matrix3d& matchCov, const TLinkNoise& noise,
									   double share = 1.0)
{
	const Eigen::Matrix3d C = matchCov + noise.floorCovariance();
	return C.inverse() / share;
}

}  // namespace lrgc
