#include <lrgc/map_builder/KeyframeReuseParams.h>
#include <lrgc/common/params_io.h>
#include <mrpt/config/CConfigFileBase.h>

namespace lrgc
{
void TKeyframeReuseParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
											  const std::string& s)
{
	rejectUnknownKeys(TKeyframeReuseParams(), c, s);
	enabled = readBool(c, s, "enabled", enabled);
	trust_keyframes = readCount(c, s, "trust_keyframes", trust_keyframes);
	min_inlier_fraction = readDouble(c, s, "min_inlier_fraction", min_inlier_fraction);
	gate_chi2 = readDouble(c, s, "gate_chi2", gate_chi2);
	requireParam(min_inlier_fraction > 0 && min_inlier_fraction <= 1, s, "min_inlier_fraction",
				 "must be in (0, 1]");
	requireParam(gate_chi2 > 0, s, "gate_chi2", "must be > 0");
}

void TKeyframeReuseParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
											const std::string& s) const
{
	writeValue(c, s, "enabled", enabled,
			   "No new keyframe where an existing one is within [MapBuilder] "
			   "keyframe_distance_m and keyframe_angle_deg and its scan agrees: the scans hang "
			   "from it (memory grows with the area mapped, not the time driven)");
	writeValue(c, s, "trust_keyframes", uint64_t(trust_keyframes),
			   "[keyframes] Keyframes are reused only within this many new keyframes of the "
			   "last loop link");
	writeValue(c, s, "min_inlier_fraction", min_inlier_fraction,
			   "Least fraction of the scan matched against the reused keyframe's scan");
	writeValue(c, s, "gate_chi2", gate_chi2,
			   "[chi2, 3 dof] Agreement of that match with the scan's registered pose");
}

}  // namespace lrgc
