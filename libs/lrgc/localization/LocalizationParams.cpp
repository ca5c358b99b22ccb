#include <lrgc/localization/LocalizationParams.h>

#include <lrgc/common/params_io.h>

#include <mrpt/config/CConfigFileBase.h>

namespace lrgc
{
void TLocalizationParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
											 const std::string& s)
{
	rejectUnknownKeys(TLocalizationParams(), c, s);
	patch_keyframes = readCount(c, s, "patch_keyframes", patch_keyframes);
	patch_max_range_m = readDouble(c, s, "patch_max_range_m", patch_max_range_m);
	track_radius_m = readDouble(c, s, "track_radius_m", track_radius_m);
	track_max_keyframes = readCount(c, s, "track_max_keyframes", track_max_keyframes);
	track_keep_share = readDouble(c, s, "track_keep_share", track_keep_share);
	min_inlier_fraction = readDouble(c, s, "min_inlier_fraction", min_inlier_fraction);
	gate_chi2 = readDouble(c, s, "gate_chi2", gate_chi2);
	lost_after = readCount(c, s, "lost_after", lost_after);
	kidnap_after = readCount(c, s, "kidnap_after", kidnap_after);
	search_budget_ms_per_s = readDouble(c, s, "search_budget_ms_per_s", search_budget_ms_per_s);
	search_resolution_m = readDouble(c, s, "search_resolution_m", search_resolution_m);
	requireParam(patch_keyframes >= 1, s, "patch_keyframes", "must be >= 1");
	requireParam(patch_max_range_m > 0, s, "patch_max_range_m", "must be > 0 m");
	requireParam(track_radius_m > 0, s, "track_radius_m", "must be > 0 m");
	requireParam(track_max_keyframes >= 1, s, "track_max_keyframes", "must be >= 1");
	requireParam(track_keep_share >= 0 && track_keep_share <= 1, s, "track_keep_share",
				 "must be in [0, 1]");
	requireParam(min_inlier_fraction >= 0 && min_inlier_fraction <= 1, s, "min_inlier_fraction",
				 "must be in [0, 1]");
	requireParam(gate_chi2 > 0, s, "gate_chi2", "must be > 0");
	requireParam(lost_after >= 1, s, "lost_after", "must be >= 1");
	requireParam(kidnap_after >= 1, s, "kidnap_after", "must be >= 1");
	requireParam(search_budget_ms_per_s > 0, s, "search_budget_ms_per_s", "must be > 0 ms/s");
	requireParam(search_resolution_m > 0, s, "search_resolution_m", "must be > 0 m");
}

void TLocalizationParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
										   const std::string& s) const
{
	writeValue(c, s, "patch_keyframes", uint64_t(patch_keyframes),
			   "Largest patch of new keyframes correlated against the whole map (tries 1, 2, "
			   "4, ... up to it)");
	writeValue(c, s, "patch_max_range_m", patch_max_range_m,
			   "[m] Patch points farther from its newest keyframe are left out");
	writeValue(c, s, "track_radius_m", track_radius_m,
			   "[m] --localize: map keyframes this close to the predicted pose are the "
			   "tracking reference");
	writeValue(c, s, "track_max_keyframes", uint64_t(track_max_keyframes),
			   "--localize: at most this many (the nearest)");
	writeValue(c, s, "track_keep_share", track_keep_share,
			   "--localize: the reference is kept while it holds the nearest keyframe and this "
			   "share of the near ones [0..1]; 1: rebuilt whenever one joins");
	writeValue(c, s, "min_inlier_fraction", min_inlier_fraction,
			   "--localize: a good match has this fraction of the scan matched [0..1]");
	writeValue(c, s, "gate_chi2", gate_chi2,
			   "--localize: ... and agrees with the odometry prior within this chi2 (3 dof)");
	writeValue(
		c, s, "lost_after", uint64_t(lost_after),
		"--localize: this many poor matches in a row: lost, relocalise by global correlation");
	writeValue(c, s, "kidnap_after", uint64_t(kidnap_after),
			   "--localize: this many scans in a row contradicting the map where the robot "
			   "is thought to be: kidnapped, relocalise on the whole map");
	writeValue(c, s, "search_budget_ms_per_s", search_budget_ms_per_s,
			   "[ms/s] --localize: modelled work per second of log of the global search "
			   "beside tracking (its results land where such a worker finishes)");
	writeValue(c, s, "search_resolution_m", search_resolution_m,
			   "[m] --localize: cell of the global searches' correlation grid (tracking "
			   "refines what they find)");
}

}  // namespace lrgc
