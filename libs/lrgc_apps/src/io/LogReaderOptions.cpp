#include "lrgc_apps/io/LogReaderOptions.h"

#include <lrgc/common/params_io.h>
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/bits_math.h>

namespace lrgc::apps
{
void TLogReaderOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
										   const std::string& section)
{
	lrgc::rejectUnknownKeys(*this, source, section);
	const double fovDeg = lrgc::readDouble(source, section, "carmen_180_beams_fov_deg",
										   mrpt::RAD2DEG(carmen_180_beams_fov));
	lrgc::requireParam(fovDeg > 0 && fovDeg <= 360, section, "carmen_180_beams_fov_deg",
					   "must be in (0, 360] (180: last beam at +90 deg; 179: at +89 deg)");
	const double maxRange =
		lrgc::readDouble(source, section, "carmen_max_range_m", carmen_max_range_m);
	lrgc::requireParam(maxRange > 0, section, "carmen_max_range_m", "must be positive");
	carmen_180_beams_fov = mrpt::DEG2RAD(fovDeg);
	carmen_max_range_m = maxRange;
}

void TLogReaderOptions::saveToConfigFile(mrpt::config::CConfigFileBase& target,
										 const std::string& section) const
{
	writeDegrees(target, section, "carmen_180_beams_fov_deg", carmen_180_beams_fov,
				 "First to last beam of a 180-beam CARMEN FLASER/RLASER [deg]: 180 or 179");
	writeValue(target, section, "carmen_max_range_m", carmen_max_range_m,
			   "CARMEN FLASER/RLASER readings >= this (less 5 mm) are no-returns [m]");
}

}  // namespace lrgc::apps
