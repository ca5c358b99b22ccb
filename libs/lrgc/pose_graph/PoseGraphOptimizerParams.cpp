#include <lrgc/pose_graph/PoseGraphOptimizerParams.h>
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/exceptions.h>
#include <lrgc/common/params_io.h>

namespace lrgc
{
void TPoseGraphOptimizerParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& src,
												   const std::string& s)
{
	rejectUnknownKeys(TPoseGraphOptimizerParams(), src, s);
	max_iterations = readInt(src, s, "max_iterations", max_iterations);
	relative_cost_tolerance =
		readDouble(src, s, "relative_cost_tolerance", relative_cost_tolerance);
	step_tolerance = readDouble(src, s, "step_tolerance", step_tolerance);
	initial_lambda = readDouble(src, s, "initial_lambda", initial_lambda);
	robust_loop_closures = readBool(src, s, "robust_loop_closures", robust_loop_closures);
	dcs_phi = readDouble(src, s, "dcs_phi", dcs_phi);
	reject_scale = readDouble(src, s, "reject_scale", reject_scale);
	requireParam(max_iterations >= 1, s, "max_iterations", "must be >= 1");
	requireParam(relative_cost_tolerance >= 0, s, "relative_cost_tolerance", "must be >= 0");
	requireParam(step_tolerance >= 0, s, "step_tolerance", "must be >= 0");
	requireParam(initial_lambda > 0, s, "initial_lambda", "must be > 0");
	requireParam(dcs_phi > 0, s, "dcs_phi", "must be > 0");
	requireParam(reject_scale > 0 && reject_scale <= 1, s, "reject_scale", "must be in (0, 1]");
}

void TPoseGraphOptimizerParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
												 const std::string& s) const
{
	const int np = mrpt::config::MRPT_SAVE_NAME_PADDING(),
			  vp = mrpt::config::MRPT_SAVE_VALUE_PADDING();
	c.write(s, "max_iterations", max_iterations, np, vp, "LM linearisations per solve [-]");
	c.write(s, "relative_cost_tolerance", relative_cost_tolerance, np, vp,
			"Stop when the cost falls by less than this fraction [-]");
	c.write(s, "step_tolerance", step_tolerance, np, vp,
			"Stop when the largest pose update is below this [m | rad]");
	c.write(s, "initial_lambda", initial_lambda, np, vp,
			"LM damping at the first step, relative to diag(H) [-]");
	c.write(s, "robust_loop_closures", robust_loop_closures, np, vp,
			"Dynamic Covariance Scaling on LoopClosure links [bool]");
	c.write(s, "dcs_phi", dcs_phi, np, vp,
			"DCS Phi: loop links with chi2 <= Phi keep full weight [chi2]");
	c.write(s, "reject_scale", reject_scale, np, vp,
			"Loop link reported as rejected if its final DCS scale is below [-]");
}

}  // namespace lrgc
