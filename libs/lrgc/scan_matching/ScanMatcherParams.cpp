/* TScanMatcherParams: load / save / validate of section [ScanMatcher]. The key set is defined
 * by saveToConfigFile(); loadFromConfigFile() rejects any other key (params_io.h). */
#include <lrgc/scan_matching/ScanMatcher.h>
#include <lrgc/common/params_io.h>
#include <mrpt/config/CConfigFileBase.h>

#include <mrpt/core/format.h>

#include <cmath>

namespace lrgc
{
void TScanMatcherParams::loadFromConfigFile(
	const mrpt::config::CConfigFileBase& c, const std::string& s)
{
	rejectUnknownKeys(TScanMatcherParams(), c, s);
	TScanMatcherParams d = *this;  // current values are the defaults of missing keys
	d.maxIterations = readInt(c, s, "max_iterations", maxIterations);
	d.maxCorrespondenceDist_m =
		readDouble(c, s, "max_correspondence_dist", maxCorrespondenceDist_m);
	d.refResolution_m = readDouble(c, s, "ref_resolution", refResolution_m);
	d.normalRadius_m = readDouble(c, s, "normal_radius", normalRadius_m);
	d.minInlierFraction = readDouble(c, s, "min_inlier_fraction", minInlierFraction);
	d.minInliers = readInt(c, s, "min_inliers", minInliers);
	d.maxRmsResidual_m = readDouble(c, s, "max_rms_residual", maxRmsResidual_m);
	d.minResidualStd_m = readDouble(c, s, "min_residual_std", minResidualStd_m);
	d.unobservableStd_m = readDouble(c, s, "unobservable_std", unobservableStd_m);
	d.wideSearchStep =
		readDouble(c, s, "wide_search_step_deg", wideSearchStep * 180 / M_PI) * M_PI / 180;
	d.wideAmbiguityMargin = readDouble(c, s, "wide_ambiguity_margin", wideAmbiguityMargin);
	d.wideMinInlierFraction =
		readDouble(c, s, "wide_min_inlier_fraction", wideMinInlierFraction);
	d.maxFreeSpaceViolation =
		readDouble(c, s, "max_free_space_violation", maxFreeSpaceViolation);
	d.validate(s);
	*this = d;
}

void TScanMatcherParams::saveToConfigFile(
	mrpt::config::CConfigFileBase& c, const std::string& s) const
{
	// No padding: MRPT 2.5.8's in-memory config keeps padded key names (with trailing blanks).
	auto wd = [&](const char* key, double v, const char* comment)
	{ c.write(s, key, mrpt::format("%.10g", v), -1, -1, comment); };
	auto wi = [&](const char* key, int v, const char* comment) { c.write(s, key, v, -1, -1, comment); };
	wi("max_iterations", maxIterations, "Gauss-Newton iterations before 'no convergence'");
	wd("max_correspondence_dist", maxCorrespondenceDist_m, "[m] initial correspondence gate (shrinks to a few residual sigmas)");
	wd("ref_resolution", refResolution_m, "[m] voxel size reducing the reference points");
	wd("normal_radius", normalRadius_m, "[m] neighbourhood radius of the reference line fits (widened x4 where sparse)");
	wd("min_inlier_fraction", minInlierFraction, "[0..1] of the scan points; fewer inliers: no match");
	wi("min_inliers", minInliers, "absolute minimum of inlier points; fewer: no match");
	wd("max_rms_residual", maxRmsResidual_m, "[m] inlier RMS residual above it: no match");
	wd("min_residual_std", minResidualStd_m, "[m] floor of the residual scale estimated from the data");
	wd("unobservable_std", unobservableStd_m, "[m] std reported along directions the scans leave free (corridor axis)");
	wd("wide_search_step_deg", wideSearchStep * 180 / M_PI, "[deg] heading step between matchWide's starting guesses");
	wd("max_free_space_violation", maxFreeSpaceViolation, "[0..1] of the scan points; more points inside space the reference saw as free: no match. Loop-closing and revisit matches; local registration uses [LocalRegistration] max_free_space_violation");
	wd("wide_ambiguity_margin", wideAmbiguityMargin, "[0..1] matchWide: lead in share of points within max_rms_residual needed over a distinct alternative and over the guess's own optimum");
	wd("wide_min_inlier_fraction", wideMinInlierFraction, "[0..1] matchWide: least fraction of the scan's points the winner must match");
}

void TScanMatcherParams::validate(const std::string& s) const
{
	requireParam(maxIterations >= 1, s, "max_iterations", "must be >= 1");
	requireParam(maxCorrespondenceDist_m > 0, s, "max_correspondence_dist", "must be > 0");
	requireParam(refResolution_m > 0 && refResolution_m < 1, s, "ref_resolution", "must be in (0, 1) m");
	requireParam(normalRadius_m > refResolution_m, s, "normal_radius", "must be > refResolution_m");
	requireParam(minInlierFraction >= 0 && minInlierFraction <= 1, s, "min_inlier_fraction", "must be in [0, 1]");
	requireParam(minInliers >= 3, s, "min_inliers", "must be >= 3 (3 DOF)");
	requireParam(maxRmsResidual_m > 0, s, "max_rms_residual", "must be > 0");
	requireParam(minResidualStd_m > 0, s, "min_residual_std", "must be > 0");
	requireParam(unobservableStd_m > 0, s, "unobservable_std", "must be > 0");
	requireParam(wideSearchStep > 0 && wideSearchStep < M_PI, s, "wide_search_step_deg", "must be in (0, 180) deg");
	requireParam(maxFreeSpaceViolation >= 0 && maxFreeSpaceViolation <= 1, s, "max_free_space_violation", "must be in [0, 1]");
	requireParam(wideAmbiguityMargin >= 0 && wideAmbiguityMargin <= 1, s, "wide_ambiguity_margin", "must be in [0, 1]");
	requireParam(wideMinInlierFraction >= 0 && wideMinInlierFraction <= 1, s, "wide_min_inlier_fraction", "must be in [0, 1]");
}

}  // namespace lrgc
