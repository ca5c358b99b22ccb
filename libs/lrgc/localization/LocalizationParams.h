/* Section [Localization]: global localisation on a saved map (the start of a log continuing
 * it, and the start and relocalisations of a localisation-only run) and scan-to-map tracking
 * (CLocalizer). Memory holds metres; units in the key comments. */
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <cstddef>
#include <string>

namespace lrgc
{
struct TLocalizationParams : public mrpt::config::CLoadableOptions
{
	/** Largest patch for global localisation [keyframes of the new log]: attempts are made
	 * when the patch holds 1, 2, 4, ... keyframes up to this, then every quarter of it with
	 * the newest this many. */
	size_t patch_keyframes = 32;
	/** [m] Patch points farther than this from the patch's newest keyframe are left out
	 * (the heading step is resolution / patch radius: farther points cost headings). */
	double patch_max_range_m = 10.0;
	/** [m] Map keyframes within this distance of the predicted pose form the tracking
	 * reference (at most track_max_keyframes, the nearest). */
	double track_radius_m = 5.0;
	size_t track_max_keyframes = 20;
	/** [0..1] The tracking reference (the joined cloud of those keyframes, whose line fits
	 * cost half the tracking) is kept while it still holds the keyframe now nearest and at
	 * least this share of the keyframes now near, and the last scan matched it well
	 * (CLocalizer::kKeepInlierFraction); else it is built again, and a scan that fails a kept
	 * reference is matched again on a new one. 1: built again whenever a keyframe joins the
	 * nearest. The four shared logs localised on their own maps: relation error within
	 * 0.0001 m or better; CPU 0.90x (ACES) and 0.63x (MIT-CSAIL) in 5 paired runs, -20 to
	 * -36 % in single runs of all four (doc/localization.md, "The tracking reference kept"). */
	double track_keep_share = 0.5;
	/** A tracking match is good if this fraction of the scan's points matched the map. */
	double min_inlier_fraction = 0.3;
	/** ... and it agrees with the odometry prior within this chi2 (3 dof) [-]. */
	double gate_chi2 = 16.27;
	/** After this many consecutive poor or failed matches the robot is lost: global
	 * localisation runs again (relocalisation) while odometry carries the pose. */
	size_t lost_after = 25;
	/** --localize: after this many scans in a row that contradict the map at the predicted
	 * pose (CLocalizer::kContradictionFraction), the robot was carried off (kidnapped):
	 * relocalise on the whole map. */
	size_t kidnap_after = 5;
	/** [ms/s] --localize: global searches run beside tracking; their results are applied
	 * where a worker doing this much modelled work (TLoopWork's model) per second of log
	 * would finish them, so offline runs are deterministic. 1000: one reference core. */
	double search_budget_ms_per_s = 1000;
	/** [m] --localize: cell of the global searches' correlation grid (the [PatchCorrelator]
	 * grid at this resolution). A found pose needs only to land where tracking's scan match
	 * converges, and the next scan is matched against the map: Intel's second half scores
	 * the same at 0.10 m as at 0.05 m (0.0229 m) for a quarter of the search work. */
	double search_resolution_m = 0.10;

	void loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
							const std::string& s) override;
	void saveToConfigFile(mrpt::config::CConfigFileBase& c,
						  const std::string& s) const override;
};

}  // namespace lrgc
