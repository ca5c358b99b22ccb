#include <lrgc/pose_graph/LinkNoise.h>

#include <lrgc/common/params_io.h>

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/bits_math.h>

namespace lrgc
{
void TLinkNoise::load(const mrpt::config::CConfigFileBase& c, const std::string& s,
					  const std::string& prefix)
{
	const std::string xyKey = prefix + "link_floor_xy_m",
					  phiKey = prefix + "link_floor_phi_deg";
	floor_xy_m = readDouble(c, s, xyKey, floor_xy_m);
	floor_phi = readDegrees(c, s, phiKey, floor_phi);
	requireParam(floor_xy_m >= 0, s, xyKey, "must be >= 0");
	requireParam(floor_phi >= 0, s, phiKey, "must be >= 0");
}

void TLinkNoise::save(mrpt::config::CConfigFileBase& c, const std::string& s,
					  const std::string& prefix, const std::string& what) const
{
	writeValue(c, s, prefix + "link_floor_xy_m", floor_xy_m, "[m] Std added to " + what);
	writeDegrees(c, s, prefix + "link_floor_phi_deg", floor_phi,
				 "[deg] Heading std added to " + what);
}

}  // namespace lrgc
