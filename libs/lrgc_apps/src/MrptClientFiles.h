/* Ready-to-run .ini files for MRPT's own programs, written into the output folder beside the
 * maps, so that an MRPT user needs no recipe:
 *
 *   pf-localization OUT/pf-localization.ini </dev/null     (headless: no window, no 3D scenes)
 *   observations2map OUT/observations2map.ini OUT/map.simplemap.gz PREFIX
 *
 * pf-localization.ini localises the mapped log on map.gridmap.gz. The map's frame has its
 * origin at the pose of the first scan mapped (doc/architecture.md), so MRPT's sample initial
 * box (metres off in another frame) cannot work: the particles start uniformly in a box of
 * +-0.5 m and +-10 deg around the first pose of trajectory.tum, which is (0, 0, 0) for a new
 * map and where the log starts in the old one for --initial-map. Its rawlog is the input when
 * it was an MRPT rawlog, the --save-rawlog conversion of a CARMEN log when one was written, or
 * a live run's capture.rawlog; else the file says how to make one. Paths are absolute, so the
 * file runs from any folder. Its filter settings (2000 particles, KLD sampling, likelihood
 * field) are those that localise SENA to a median 0.11 m (tests/pf_localization_test.cpp).
 *
 * observations2map.ini rebuilds the grid from map.simplemap.gz with our grid's resolution and
 * ray length ([MappingApplication], the section observations2map reads by default). */
#pragma once

#include <lrgc/map_builder/Trajectory.h>

#include <string>

namespace lrgc::apps
{
struct TRunOutputsSnapshot;

/** pf-localization.ini for the map in `outDir`: `rawlog` the MRPT rawlog to localise (empty:
 * none, the file says how to make one), `startPose` the pose of its first scan in the map. */
std::string pfLocalizationIni(const std::string& outDir, const std::string& rawlog,
							  const mrpt::math::TPose2D& startPose, double resolution);

/** observations2map.ini: an occupancy grid of `resolution` [m], rays up to `maxRange` [m]. */
std::string observations2mapIni(double resolution, double maxRange);

/** Writes both into `outDir` (atomically), for a run that mapped at least one scan. */
void writeMrptClientFiles(const TRunOutputsSnapshot& s, const std::string& outDir);

}  // namespace lrgc::apps
