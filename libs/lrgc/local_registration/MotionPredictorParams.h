/* Section [MotionPredictor]: the parameters of CMotionPredictor, apart from the class so that
 * the map builder's public header (MapBuilderParams.h) needs none of the stage's internals. */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/core/bits_math.h>

#include <cmath>
#include <cstddef>
#include <string>

namespace lrgc
{
struct TMotionPredictorParams : public mrpt::config::CLoadableOptions
{
	bool use_odometry = true;        //!< false: ignore odometry, constant-velocity model only
	double sigma_floor_xy_m = 0.01;  //!< [m] odometry noise floor per step
	double sigma_floor_phi = mrpt::DEG2RAD(0.5);  //!< [rad] (key sigma_floor_phi_deg)
	double k_xy_m_per_m = 0.1;       //!< [m/m] translational noise per metre travelled
	double k_xy_m_per_rad = 0.05;    //!< [m/rad] translational noise per radian turned
	double k_phi_rad_per_m = 0.05;   //!< [rad/m] rotational noise per metre travelled
	double k_phi_rad_per_rad = 0.1;  //!< [rad/rad] rotational noise per radian turned
	/** [m] The per-metre terms are proportional (std = k d) up to this distance, the length
	 * over which odometry errors stay correlated; a longer odometry-only motion (scans
	 * skipped in a hall the laser cannot see across) is a chain of independent pieces this
	 * long, whose variances add: std = k sqrt(L d). Keyframe steps (0.3 m) are below it. */
	double noise_correlation_length_m = 1.0;
	double cv_sigma_xy_m = 0.3;  //!< [m] constant-velocity model: std dev per step
	double cv_sigma_phi = mrpt::DEG2RAD(20.0);  //!< [rad] (key cv_sigma_phi_deg)

	void loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
							const std::string& s) override;
	void saveToConfigFile(mrpt::config::CConfigFileBase& c,
						  const std::string& s) const override;
};

}  // namespace lrgc
