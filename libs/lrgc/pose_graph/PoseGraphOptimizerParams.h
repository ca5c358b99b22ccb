/* Section [PoseGraphOptimizer]: the parameters of CPoseGraphOptimizer, apart from the class so
 * that the map builder's public header (MapBuilderParams.h) needs none of the stage's
 * internals. */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/core/bits_math.h>

#include <cmath>
#include <cstddef>
#include <string>

namespace lrgc
{
/** Section [PoseGraphOptimizer]. */
struct TPoseGraphOptimizerParams : public mrpt::config::CLoadableOptions
{
	int max_iterations = 50;  //!< LM linearisations per solve, all stages together [-]
	double relative_cost_tolerance = 1e-4;  //!< stop when the cost falls by less than this [-]
											//!< (1e-6: +10% Intel time, same error)
	double step_tolerance = 1e-7;  //!< stop when the largest step component is below [m|rad]
	double initial_lambda = 1e-6;  //!< LM damping relative to diag(H) at the first step [-]
	bool robust_loop_closures =
		true;  //!< DCS on LoopClosure links (false: plain least squares)
	double dcs_phi =
		5.0;  //!< DCS Phi [chi2 units]: loop links with chi2 <= Phi keep full weight
	double reject_scale = 0.1;  //!< a loop link with final DCS s below this counts as rejected

	void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
							const std::string& section) override;
	void saveToConfigFile(mrpt::config::CConfigFileBase& target,
						  const std::string& section) const override;
};

}  // namespace lrgc
