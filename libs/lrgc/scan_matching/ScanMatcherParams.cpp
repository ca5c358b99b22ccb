/* TScanMatcherParams: load / save / validate of section [ScanMatcher]. The key set is defined
 * by saveToConfigFile(); loadFromConfigFile() rejects any other key (params_io.h). */
#include <lrgc/scan_matching/ScanMatcher.h>
#include <lrgc/common/params_io.h>
#include <mrpt/config/CConfigFileBase.h>

#include <mrpt/core/format.h>

#include <cmath>

namespace lrgc
{
void TScanMatcherParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
											const std::string& s)
{
	rejectUnknownKeys(TScanMatcherParams(), c, s);
	TScanMatcherParams d = *this;  // current values are the defaults of missing keys
	d.max_iterations = readInt(c, s, "max_iterations", max_iterations);
	d.max_correspondence_dist_m =
		readDouble(c, s, "max_correspondence_dist_m", max_correspondence_dist_m);
	d.ref_resolution_m = readDouble(c, s, "ref_resolution_m", ref_resolution_m);
	d.normal_radius_m = readDouble(c, s, "normal_radius_m", normal_radius_m);
	d.far_fit_angle = readDegrees(c, s, "far_fit_angle_deg", far_fit_angle);
	d.far_fit_max_radius_m = readDouble(c, s, "far_fit_max_radius_m", far_fit_max_radius_m);
	d.min_inlier_fraction = readDouble(c, s, "min_inlier_fraction", min_inlier_fraction);
	d.min_inliers = readInt(c, s, "min_inliers", min_inliers);
	d.max_rms_residual_m = readDouble(c, s, "max_rms_residual_m", max_rms_residual_m);
	d.min_residual_std_m = readDouble(c, s, "min_residual_std_m", min_residual_std_m);
	d.unobservable_std_m = readDouble(c, s, "unobservable_std_m", unobservable_std_m);
	d.wide_search_step = readDegrees(c, s, "wide_search_step_deg", wide_search_step);
	d.wide_ambiguity_margin = readDouble(c, s, "wide_ambiguity_margin", wide_ambiguity_margin);
	d.wide_min_inlier_fraction =
		readDouble(c, s, "wide_min_inlier_fraction", wide_min_inlier_fraction);
	d.max_free_space_violation =
		readDouble(c, s, "max_free_space_violation", max_free_space_violation);
	d.validate(s);
	*this = d;
}

void TScanMatcherParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
										  const std::string& s) const
{
	writeValue(c, s, "max_iterations", max_iterations,
			   "Gauss-Newton iterations before 'no convergence'");
	writeValue(c, s, "max_correspondence_dist_m", max_correspondence_dist_m,
			   "[m] initial correspondence gate (shrinks to a few residual sigmas)");
	writeValue(c, s, "ref_resolution_m", ref_resolution_m,
			   "[m] voxel size reducing the reference points");
	writeValue(c, s, "normal_radius_m", normal_radius_m,
			   "[m] neighbourhood radius of the reference line fits (widened x4 where sparse)");
	writeDegrees(c, s, "far_fit_angle_deg", far_fit_angle,
				 "[deg] a point with no line within 4 normal_radius_m is fitted again within "
				 "range x this (a long-range laser's far walls); 0: off");
	writeValue(c, s, "far_fit_max_radius_m", far_fit_max_radius_m,
			   "[m] the far fit's widest neighbourhood");
	writeValue(c, s, "min_inlier_fraction", min_inlier_fraction,
			   "[0..1] of the scan points; fewer inliers: no match");
	writeValue(c, s, "min_inliers", min_inliers,
			   "absolute minimum of inlier points; fewer: no match");
	writeValue(c, s, "max_rms_residual_m", max_rms_residual_m,
			   "[m] inlier RMS residual above it: no match");
	writeValue(c, s, "min_residual_std_m", min_residual_std_m,
			   "[m] floor of the residual scale estimated from the data");
	writeValue(c, s, "unobservable_std_m", unobservable_std_m,
			   "[m] std reported along directions the scans leave free (corridor axis)");
	writeDegrees(c, s, "wide_search_step_deg", wide_search_step,
				 "[deg] heading step between matchWide's starting guesses");
	writeValue(c, s, "max_free_space_violation", max_free_space_violation,
			   "[0..1] of the scan points; more points inside space the reference saw as free: "
			   "no match. Loop-closing and revisit matches; local registration uses "
			   "[LocalRegistration] max_free_space_violation");
	writeValue(c, s, "wide_ambiguity_margin", wide_ambiguity_margin,
			   "[0..1] matchWide: lead in share of points within max_rms_residual_m needed "
			   "over a distinct alternative and over the guess's own optimum");
	writeValue(c, s, "wide_min_inlier_fraction", wide_min_inlier_fraction,
			   "[0..1] matchWide: least fraction of the scan's points the winner must match");
}

void TScanMatcherParams::validate(const std::string& s) const
{
	requireParam(max_iterations >= 1, s, "max_iterations", "must be >= 1");
	requireParam(max_correspondence_dist_m > 0, s, "max_correspondence_dist_m", "must be > 0");
	requireParam(ref_resolution_m > 0 && ref_resolution_m < 1, s, "ref_resolution_m",
				 "must be in (0, 1) m");
	requireParam(normal_radius_m > ref_resolution_m, s, "normal_radius_m",
				 "must be > ref_resolution_m");
	requireParam(far_fit_angle >= 0 && far_fit_angle < M_PI / 2, s, "far_fit_angle_deg",
				 "must be in [0, 90) deg");
	requireParam(far_fit_max_radius_m > 0, s, "far_fit_max_radius_m", "must be > 0");
	requireParam(min_inlier_fraction >= 0 && min_inlier_fraction <= 1, s, "min_inlier_fraction",
				 "must be in [0, 1]");
	requireParam(min_inliers >= 3, s, "min_inliers", "must be >= 3 (3 DOF)");
	requireParam(max_rms_residual_m > 0, s, "max_rms_residual_m", "must be > 0");
	requireParam(min_residual_std_m > 0, s, "min_residual_std_m", "must be > 0");
	requireParam(unobservable_std_m > 0, s, "unobservable_std_m", "must be > 0");
	requireParam(wide_search_step > 0 && wide_search_step < M_PI, s, "wide_search_step_deg",
				 "must be in (0, 180) deg");
	requireParam(max_free_space_violation >= 0 && max_free_space_violation <= 1, s,
				 "max_free_space_violation", "must be in [0, 1]");
	requireParam(wide_ambiguity_margin >= 0 && wide_ambiguity_margin <= 1, s,
				 "wide_ambiguity_margin", "must be in [0, 1]");
	requireParam(wide_min_inlier_fraction >= 0 && wide_min_inlier_fraction <= 1, s,
				 "wide_min_inlier_fraction", "must be in [0, 1]");
}

}  // namespace lrgc
