/* Options of the log readers (section [LogReader]).
 *
 * CARMEN beam geometry. A FLASER/RLASER line does not state its angles. The first beam points
 * at -90 deg (right of the laser), the beams sweep counter-clockwise. With 361 beams the step
 * is 0.5 deg (-90..+90); in general n beams span 180 deg (step 180/(n-1) deg), except for
 * n = 180 where the logs do not say whether the last beam is at +90 deg (span 180, step
 * 180/179 deg) or at +89 deg (span 179, step 1 deg): `carmen_180_beams_fov_deg` chooses.
 * ROBOTLASER1 lines carry their own start angle, resolution and maximum range.
 *
 * CARMEN no-returns. Measured on the benchmark logs (zcat *.clf.gz): a beam without a return
 * is recorded as one sentinel value at the sensor's limit: 81.83 m (Intel, largest real
 * reading 26.37 m), 81.91 m (MIT-CSAIL, largest real 42.40 m), 50.00 m (ACES, largest real
 * 49.91 m); CARMEN drivers also write 80.0 m. The rule: a FLASER/RLASER reading
 * r >= carmen_max_range_m - 5 mm (half the 1 cm quantisation of the logs) is a no-return,
 * and so are +inf and r = 0 (some drivers' "no echo"); a ROBOTLASER1 reading compares with
 * the line's own maximum_range instead.
 * A no-return is stored as r = maxRange with the invalid flag: never an obstacle. The default
 * of 50 m catches every sentinel above while keeping every real reading of the three logs;
 * a log of a shorter-range laser (e.g. a 30 m Hokuyo writing 30.0 for no-return) needs
 * carmen_max_range_m set to its limit. NaN and negative readings are marked invalid and
 * reported.
 */
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <cmath>

namespace lrgc::apps
{
struct TLogReaderOptions : public mrpt::config::CLoadableOptions
{
	/** Angle from the first to the last beam of a 180-beam FLASER/RLASER [rad]; the first
	 * beam is at -90 deg. 180 deg (step 180/179) or 179 deg (step 1 deg). Measured on the
	 * Intel log (relation metric, everything else equal): 179 deg gives 0.015 m mean
	 * translational error, 180 deg 0.055 m; so the SICK's 1-degree mode, -90..+89 deg. */
	double carmen_180_beams_fov = 179.0 * M_PI / 180.0;
	/** FLASER/RLASER readings at or above this (less 5 mm) are no-returns [m]. */
	double carmen_max_range_m = 50.0;

	/** Reads the keys of `section`; unknown keys and invalid values throw. */
	void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
							const std::string& section) override;
	void saveToConfigFile(mrpt::config::CConfigFileBase& target,
						  const std::string& section) const override;
};

}  // namespace lrgc::apps
