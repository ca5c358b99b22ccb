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
	writeValue(c, s, "max_iterations", max_iterations, "LM linearisations per solve [-]");
	writeValue(c, s, "relative_cost_tolerance", relative_cost_tolerance,
			   "Stop when the cost falls by less than this fraction [-]");
	writeValue(c, s, "step_tolerance", step_tolerance,
			   "Stop when the largest pose update is below this [m | rad]");
	writeValue(c, s, "initial_lambda", initial_lambda,
			   "LM damping at the first step, relative to diag(H) [-]");
	writeValue(c, s, "robust_loop_closures", robust_loop_closures,
			   "Dynamic Covariance Scaling on LoopClosure links [bool]");
	writeValue(c, s, "dcs_phi", dcs_phi,
			   "DCS Phi: loop links with chi2 <= Phi keep full weight [chi2]");
	writeValue(c, s, "reject_scale", reject_scale,
			   "Loop link reported as rejected if its final DCS scale is below [-]");
}

}  // namespace lrgc
