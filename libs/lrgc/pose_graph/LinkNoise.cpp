#include <lrgc/pose_graph/LinkNoise.h>

#include <lrgc/common/params_io.h>

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/bits_math.h>

namespace lrgc
{
void TLinkNoise::load(
	const mrpt::config::CConfigFileBase& c, const std::string& s, const std::string& prefix)
{
	const std::string xyKey = prefix + "link_floor_xy_m", phiKey = prefix + "link_floor_phi_deg";
	floor_xy_m = readDouble(c, s, xyKey, floor_xy_m);
	floor_phi = readDegrees(c, s, phiKey, floor_phi);
	requireParam(floor_xy_m >= 0, s, xyKey, "must be >= 0");
	requireParam(floor_phi >= 0, s, phiKey, "must be >= 0");
}

void TLinkNoise::save(
	mrpt::config::CConfigFileBase& c, const std::string& s, const std::string& prefix,
	const std::string& what) const
{
	const int np = mrpt::config::MRPT_SAVE_NAME_PADDING(), vp = mrpt::config::MRPT_SAVE_VALUE_PADDING();
	c.write(s, prefix + "link_floor_xy_m", floor_xy_m, np, vp, "[m] Std added to " + what);
	c.write(s, prefix + "link_floor_phi_deg", mrpt::RAD2DEG(floor_phi), np, vp,
			"[deg] Heading std added to " + what);
}

}  // namespace lrgc
