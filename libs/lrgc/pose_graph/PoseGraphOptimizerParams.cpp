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
	maxIterations = readInt(src, s, "max_iterations", maxIterations);
	relativeCostTolerance =
		readDouble(src, s, "relative_cost_tolerance", relativeCostTolerance);
	stepTolerance = readDouble(src, s, "step_tolerance", stepTolerance);
	initialLambda = readDouble(src, s, "initial_lambda", initialLambda);
	robustLoopClosures = readBool(src, s, "robust_loop_closures", robustLoopClosures);
	dcsPhi = readDouble(src, s, "dcs_phi", dcsPhi);
	rejectScale = readDouble(src, s, "reject_scale", rejectScale);
	requireParam(maxIterations >= 1, s, "max_iterations", "must be >= 1");
	requireParam(relativeCostTolerance >= 0, s, "relative_cost_tolerance", "must be >= 0");
	requireParam(stepTolerance >= 0, s, "step_tolerance", "must be >= 0");
	requireParam(initialLambda > 0, s, "initial_lambda", "must be > 0");
	requireParam(dcsPhi > 0, s, "dcs_phi", "must be > 0");
	requireParam(rejectScale > 0 && rejectScale <= 1, s, "reject_scale", "must be in (0, 1]");
}

void TPoseGraphOptimizerParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
												 const std::string& s) const
{
	const int np = mrpt::config::MRPT_SAVE_NAME_PADDING(),
			  vp = mrpt::config::MRPT_SAVE_VALUE_PADDING();
	c.write(s, "max_iterations", maxIterations, np, vp, "LM linearisations per solve [-]");
	c.write(s, "relative_cost_tolerance", relativeCostTolerance, np, vp,
			"Stop when the cost falls by less than this fraction [-]");
	c.write(s, "step_tolerance", stepTolerance, np, vp,
			"Stop when the largest pose update is below this [m | rad]");
	c.write(s, "initial_lambda", initialLambda, np, vp,
			"LM damping at the first step, relative to diag(H) [-]");
	c.write(s, "robust_loop_closures", robustLoopClosures, np, vp,
			"Dynamic Covariance Scaling on LoopClosure links [bool]");
	c.write(s, "dcs_phi", dcsPhi, np, vp,
			"DCS Phi: loop links with chi2 <= Phi keep full weight [chi2]");
	c.write(s, "reject_scale", rejectScale, np, vp,
			"Loop link reported as rejected if its final DCS scale is below [-]");
}

}  // namespace lrgc
