#include <lrgc/local_registration/MotionPredictorParams.h>
#include <lrgc/common/params_io.h>
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/bits_math.h>

namespace lrgc
{
void TMotionPredictorParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
												const std::string& s)
{
	rejectUnknownKeys(TMotionPredictorParams(), c, s);
	use_odometry = readBool(c, s, "use_odometry", use_odometry);
	sigma_floor_xy_m = readDouble(c, s, "sigma_floor_xy_m", sigma_floor_xy_m);
	sigma_floor_phi = readDegrees(c, s, "sigma_floor_phi_deg", sigma_floor_phi);
	k_xy_m_per_m = readDouble(c, s, "k_xy_m_per_m", k_xy_m_per_m);
	k_xy_m_per_rad = readDouble(c, s, "k_xy_m_per_rad", k_xy_m_per_rad);
	k_phi_rad_per_m = readDouble(c, s, "k_phi_rad_per_m", k_phi_rad_per_m);
	k_phi_rad_per_rad = readDouble(c, s, "k_phi_rad_per_rad", k_phi_rad_per_rad);
	noise_correlation_length_m =
		readDouble(c, s, "noise_correlation_length_m", noise_correlation_length_m);
	cv_sigma_xy_m = readDouble(c, s, "cv_sigma_xy_m", cv_sigma_xy_m);
	cv_sigma_phi = readDegrees(c, s, "cv_sigma_phi_deg", cv_sigma_phi);
	for (const auto& [key, v] : {std::pair{"sigma_floor_xy_m", sigma_floor_xy_m},
								 {"sigma_floor_phi_deg", sigma_floor_phi},
								 {"cv_sigma_xy_m", cv_sigma_xy_m},
								 {"cv_sigma_phi_deg", cv_sigma_phi},
								 {"noise_correlation_length_m", noise_correlation_length_m}})
		requireParam(v > 0, s, key, "must be > 0");
	for (const auto& [key, v] : {std::pair{"k_xy_m_per_m", k_xy_m_per_m},
								 {"k_xy_m_per_rad", k_xy_m_per_rad},
								 {"k_phi_rad_per_m", k_phi_rad_per_m},
								 {"k_phi_rad_per_rad", k_phi_rad_per_rad}})
		requireParam(v >= 0, s, key, "must be >= 0");
}

void TMotionPredictorParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
											  const std::string& s) const
{
	writeValue(c, s, "use_odometry", use_odometry,
			   "Use wheel odometry if the log has it (else constant velocity)");
	writeValue(c, s, "sigma_floor_xy_m", sigma_floor_xy_m, "[m] Odometry noise floor per step");
	writeDegrees(c, s, "sigma_floor_phi_deg", sigma_floor_phi,
				 "[deg] Odometry heading noise floor per step");
	writeValue(c, s, "k_xy_m_per_m", k_xy_m_per_m,
			   "[m/m] Translational noise per metre travelled");
	writeValue(c, s, "k_xy_m_per_rad", k_xy_m_per_rad,
			   "[m/rad] Translational noise per radian turned");
	writeValue(c, s, "k_phi_rad_per_m", k_phi_rad_per_m,
			   "[rad/m] Heading noise per metre travelled");
	writeValue(c, s, "k_phi_rad_per_rad", k_phi_rad_per_rad,
			   "[rad/rad] Heading noise per radian turned");
	writeValue(c, s, "noise_correlation_length_m", noise_correlation_length_m,
			   "[m] Per-metre noise is proportional up to this distance, random-walk (std ~ "
			   "sqrt) beyond");
	writeValue(c, s, "cv_sigma_xy_m", cv_sigma_xy_m,
			   "[m] Constant-velocity model (no odometry): std dev per step");
	writeDegrees(c, s, "cv_sigma_phi_deg", cv_sigma_phi,
				 "[deg] Constant-velocity model: heading std dev per step");
}

}  // namespace lrgc
