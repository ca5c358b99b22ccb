#include <lrgc/loop_closing/RevisitLinkerParams.h>
#include <lrgc/common/params_io.h>
#include <mrpt/config/CConfigFileBase.h>

namespace lrgc
{
void TRevisitLinkerParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
											  const std::string& s)
{
	rejectUnknownKeys(TRevisitLinkerParams(), c, s);
	enabled = readBool(c, s, "enabled", enabled);
	radius_m = readDouble(c, s, "radius_m", radius_m);
	max_phi = readDegrees(c, s, "max_phi_deg", max_phi);
	min_index_gap = readCount(c, s, "min_index_gap", min_index_gap);
	min_path_gap_m = readDouble(c, s, "min_path_gap_m", min_path_gap_m);
	any_heading = readBool(c, s, "any_heading", any_heading);
	stride = readCount(c, s, "stride", stride);
	patch_check_keyframes = readCount(c, s, "patch_check_keyframes", patch_check_keyframes);
	ambiguity_check = readBool(c, s, "ambiguity_check", ambiguity_check);
	max_heading_std = readDegrees(c, s, "max_heading_std_deg", max_heading_std);
	region_retry = readBool(c, s, "region_retry", region_retry);
	region_min_isolated_share =
		readDouble(c, s, "region_min_isolated_share", region_min_isolated_share);
	min_inlier_fraction = readDouble(c, s, "min_inlier_fraction", min_inlier_fraction);
	gate_chi2 = readDouble(c, s, "gate_chi2", gate_chi2);
	prior_std_xy_m = readDouble(c, s, "prior_std_xy_m", prior_std_xy_m);
	prior_std_phi = readDegrees(c, s, "prior_std_phi_deg", prior_std_phi);
	requireParam(radius_m > 0, s, "radius_m", "must be > 0");
	requireParam(min_path_gap_m >= 0, s, "min_path_gap_m", "must be >= 0");
	requireParam(max_phi > 0 && max_phi <= M_PI, s, "max_phi_deg", "must be in (0, 180]");
	requireParam(stride >= 1, s, "stride", "must be >= 1");
	requireParam(min_inlier_fraction > 0 && min_inlier_fraction <= 1, s, "min_inlier_fraction",
				 "must be in (0, 1]");
	requireParam(region_min_isolated_share >= 0 && region_min_isolated_share <= 1, s,
				 "region_min_isolated_share", "must be in [0, 1]");
	requireParam(gate_chi2 > 0, s, "gate_chi2", "must be > 0");
	requireParam(max_heading_std >= 0, s, "max_heading_std_deg", "must be >= 0");
	requireParam(prior_std_xy_m > 0, s, "prior_std_xy_m", "must be > 0");
	requireParam(prior_std_phi > 0, s, "prior_std_phi_deg", "must be > 0");
}

void TRevisitLinkerParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
											const std::string& s) const
{
	writeValue(c, s, "enabled", enabled,
			   "End of run: scan match revisited places the online gate missed");
	writeValue(c, s, "radius_m", radius_m,
			   "[m] Old keyframes this close to a keyframe are candidates");
	writeDegrees(c, s, "max_phi_deg", max_phi, "[deg] ... and this close in heading");
	writeValue(c, s, "min_index_gap", uint64_t(min_index_gap),
			   "Candidates are older than this many keyframes");
	writeValue(c, s, "min_path_gap_m", min_path_gap_m,
			   "[m] ... and lie at least this much path back");
	writeValue(c, s, "any_heading", any_heading,
			   "Match a keyframe facing away from every near old one against them all");
	writeValue(c, s, "stride", uint64_t(stride), "Every stride-th keyframe is tried");
	writeValue(c, s, "patch_check_keyframes", uint64_t(patch_check_keyframes),
			   "A match must agree with that of the keyframe +- this many (0: not checked)");
	writeValue(c, s, "ambiguity_check", ambiguity_check,
			   "A match must explain more of the scan than any other optimum within the prior");
	writeDegrees(c, s, "max_heading_std_deg", max_heading_std,
				 "[deg] A match must fix the heading at its position to this std (0: any)");
	writeValue(c, s, "region_retry", region_retry,
			   "A failed match against one old scan of mostly isolated returns is matched "
			   "again against the old map's region");
	writeValue(
		c, s, "region_min_isolated_share", region_min_isolated_share,
		"[0..1] ... where at least this share of that scan's points are isolated returns");
	writeValue(c, s, "min_inlier_fraction", min_inlier_fraction,
			   "Least fraction of the keyframe's points matched");
	writeValue(c, s, "gate_chi2", gate_chi2,
			   "[chi2, 3 dof] Agreement of the match with the current relative pose");
	writeValue(c, s, "prior_std_xy_m", prior_std_xy_m,
			   "[m] Std of the current relative pose (loop-closed map)");
	writeDegrees(c, s, "prior_std_phi_deg", prior_std_phi,
				 "[deg] Heading std of the current relative pose");
}

}  // namespace lrgc
