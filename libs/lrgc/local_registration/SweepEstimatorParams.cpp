#include <lrgc/local_registration/SweepEstimatorParams.h>
#include <lrgc/common/params_io.h>
#include <mrpt/config/CConfigFileBase.h>

namespace lrgc
{
void TSweepEstimatorParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
											   const std::string& s)
{
	rejectUnknownKeys(TSweepEstimatorParams(), c, s);
	enabled = readBool(c, s, "enabled", enabled);
	max_sweep_time_s = readDouble(c, s, "max_sweep_time_s", max_sweep_time_s);
	min_rate_change_per_s =
		readDegrees(c, s, "min_rate_change_deg_per_s", min_rate_change_per_s);
	min_samples = readCount(c, s, "min_samples", min_samples);
	max_std_s = readDouble(c, s, "max_std_s", max_std_s);
	requireParam(max_sweep_time_s > 0 && max_sweep_time_s < 1, s, "max_sweep_time_s",
				 "must be in (0, 1) s");
	requireParam(min_rate_change_per_s > 0, s, "min_rate_change_deg_per_s", "must be > 0");
	requireParam(min_samples >= 3, s, "min_samples", "must be >= 3");
	requireParam(max_std_s > 0, s, "max_std_s", "must be > 0");
}

void TSweepEstimatorParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
											 const std::string& s) const
{
	writeValue(c, s, "enabled", enabled,
			   "Estimate the laser's sweep time from the scans of turns when [MapBuilder] "
			   "scan_sweep_time_s = 0");
	writeValue(c, s, "max_sweep_time_s", max_sweep_time_s, "[s] Largest sweep time considered");
	writeDegrees(c, s, "min_rate_change_deg_per_s", min_rate_change_per_s,
				 "[deg/s] A scan is compared with a recent one turning at least this much "
				 "faster or slower");
	writeValue(c, s, "min_samples", uint64_t(min_samples),
			   "Compared scan pairs before an estimate is used");
	writeValue(c, s, "max_std_s", max_std_s,
			   "[s] An estimate is used once its standard error is below this");
}

}  // namespace lrgc
