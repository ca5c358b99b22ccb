/* Section [SweepEstimator]: the parameters of CSweepEstimator (online estimation of the
 * laser's sweep time for de-skewing), apart from the class so that the map builder's public
 * header needs none of the stage's internals. */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/core/bits_math.h>

#include <cstddef>
#include <string>

namespace lrgc
{
struct TSweepEstimatorParams : public mrpt::config::CLoadableOptions
{
	/** Estimate the sweep time from the scans when [MapBuilder] scan_sweep_time_s is 0 (a
	 * nonzero scan_sweep_time_s is a fixed, calibrated value and wins). Off by default: it
	 * helps MIT-CSAIL and Killian and hurts Intel and ACES (doc/scan-matching.md). */
	bool enabled = false;
	double max_sweep_time_s =
		0.1;  //!< [s] largest sweep time considered (a 10 Hz 360 deg lidar)
	/** [rad/s] a scan is compared with a recent one whose turn rate differs by at least
	 * this much (key min_rate_change_deg_per_s): equal rates stretch both scans alike. */
	double min_rate_change_per_s = mrpt::DEG2RAD(10.0);
	size_t min_samples = 30;  //!< compared pairs before an estimate is used
	/** [s] an estimate is used once its standard error is below this */
	double max_std_s = 0.002;

	void loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
							const std::string& s) override;
	void saveToConfigFile(mrpt::config::CConfigFileBase& c,
						  const std::string& s) const override;
};

}  // namespace lrgc
