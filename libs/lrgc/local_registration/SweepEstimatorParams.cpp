#include <lrgc/local_registration/SweepEstimatorParams.h>
#include <lrgc/common/params_io.h>
#include <mrpt/config/CConfigFileBase.h>

namespace lrgc
{
void TSweepEstimatorParams::loadFromConfigFile(
	const mrpt::config::CConfigFileBase& c, const std::string& s)
{
	rejectUnknownKeys(TSweepEstimatorParams(), c, s);
	enabled = readBool(c, s, "enabled", enabled);
	max_sweep_time_s = readDouble(c, s, "max_sweep_time_s", max_sweep_time_s);
	min_rate_change_per_s = readDegrees(c, s, "min_rate_change_deg_per_s", min_rate_change_per_s);
	min_samples = readCount(c, s, "min_samples", min_samples);
	max_std_s = readDouble(c, s, "max_std_s", max_std_s);
	requireParam(
		max_sweep_time_s > 0 && max_sweep_time_s < 1, s, "max_sweep_time_s", "must be in (0, 1) s");
	requireParam(min_rate_change_per_s > 0, s, "min_rate_change_deg_per_s", "must be > 0");
	requireParam(min_samples >= 3, s, "min_samples", "must be >= 3");
	requireParam(max_std_s > 0, s, "max_std_s", "must be > 0");
}

void TSweepEstimatorParams::saveToConfigFile(
	mrpt::config::CConfigFileBase& c, const std::string& s) const
{
	const int np = mrpt::config::MRPT_SAVE_NAME_PADDING(), vp = mrpt::config::MRPT_SAVE_VALUE_PADDING();
	c.write(s, "enabled", enabled, np, vp, "Estimate the laser's sweep time from the scans of turns when [MapBuilder] scan_sweep_time_s = 0");
	c.write(s, "max_sweep_time_s", max_sweep_time_s, np, vp, "[s] Largest sweep time considered");
	c.write(s, "min_rate_change_deg_per_s", mrpt::RAD2DEG(min_rate_change_per_s), np, vp, "[deg/s] A scan is compared with a recent one turning at least this much faster or slower");
	c.write(s, "min_samples", uint64_t(min_samples), np, vp, "Compared scan pairs before an estimate is used");
	c.write(s, "max_std_s", max_std_s, np, vp, "[s] An estimate is used once its standard error is below this");
}

}  // namespace lrgc
