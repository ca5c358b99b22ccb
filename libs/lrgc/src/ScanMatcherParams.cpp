/* TScanMatcherParams: load / save / validate of section [ScanMatcher]. The key set is defined
 * by saveToConfigFile(); loadFromConfigFile() rejects any other key (params_io.h). */
#include <lrgc/ScanMatcher.h>
#include <lrgc/params_io.h>
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
	d.maxIterations = c.read_int(s, "maxIterations", maxIterations);
	d.maxCorrespondenceDist_m = c.read_double(s, "maxCorrespondenceDist_m", maxCorrespondenceDist_m);
	d.refResolution_m = c.read_double(s, "refResolution_m", refResolution_m);
	d.normalRadius_m = c.read_double(s, "normalRadius_m", normalRadius_m);
	d.minInlierFraction = c.read_double(s, "minInlierFraction", minInlierFraction);
	d.minInliers = c.read_int(s, "minInliers", minInliers);
	d.maxRmsResidual_m = c.read_double(s, "maxRmsResidual_m", maxRmsResidual_m);
	d.minResidualStd_m = c.read_double(s, "minResidualStd_m", minResidualStd_m);
	d.unobservableStd_m = c.read_double(s, "unobservableStd_m", unobservableStd_m);
	d.wideSearchStep =
		c.read_double(s, "wideSearchStep_deg", wideSearchStep * 180 / M_PI) * M_PI / 180;
	d.wideAmbiguityMargin = c.read_double(s, "wideAmbiguityMargin", wideAmbiguityMargin);
	d.maxFreeSpaceViolation = c.read_double(s, "maxFreeSpaceViolation", maxFreeSpaceViolation);
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
	wi("maxIterations", maxIterations, "Gauss-Newton iterations before 'no convergence'");
	wd("maxCorrespondenceDist_m", maxCorrespondenceDist_m, "[m] initial correspondence gate (shrinks to a few residual sigmas)");
	wd("refResolution_m", refResolution_m, "[m] voxel size reducing the reference points");
	wd("normalRadius_m", normalRadius_m, "[m] neighbourhood radius of the reference line fits (widened x4 where sparse)");
	wd("minInlierFraction", minInlierFraction, "[0..1] of the scan points; fewer inliers: no match");
	wi("minInliers", minInliers, "absolute minimum of inlier points; fewer: no match");
	wd("maxRmsResidual_m", maxRmsResidual_m, "[m] inlier RMS residual above it: no match");
	wd("minResidualStd_m", minResidualStd_m, "[m] floor of the residual scale estimated from the data");
	wd("unobservableStd_m", unobservableStd_m, "[m] std reported along directions the scans leave free (corridor axis)");
	wd("wideSearchStep_deg", wideSearchStep * 180 / M_PI, "[deg] heading step between matchWide's starting guesses");
	wd("maxFreeSpaceViolation", maxFreeSpaceViolation, "[0..1] of the scan points; more points inside space the reference saw as free: no match");
	wd("wideAmbiguityMargin", wideAmbiguityMargin, "[0..1] matchWide: inlier fraction lead needed over a distinct alternative");
}

void TScanMatcherParams::validate(const std::string& s) const
{
	requireParam(maxIterations >= 1, s, "maxIterations", "must be >= 1");
	requireParam(maxCorrespondenceDist_m > 0, s, "maxCorrespondenceDist_m", "must be > 0");
	requireParam(refResolution_m > 0 && refResolution_m < 1, s, "refResolution_m", "must be in (0, 1) m");
	requireParam(normalRadius_m > refResolution_m, s, "normalRadius_m", "must be > refResolution_m");
	requireParam(minInlierFraction >= 0 && minInlierFraction <= 1, s, "minInlierFraction", "must be in [0, 1]");
	requireParam(minInliers >= 3, s, "minInliers", "must be >= 3 (3 DOF)");
	requireParam(maxRmsResidual_m > 0, s, "maxRmsResidual_m", "must be > 0");
	requireParam(minResidualStd_m > 0, s, "minResidualStd_m", "must be > 0");
	requireParam(unobservableStd_m > 0, s, "unobservableStd_m", "must be > 0");
	requireParam(wideSearchStep > 0 && wideSearchStep < M_PI, s, "wideSearchStep_deg", "must be in (0, 180) deg");
	requireParam(maxFreeSpaceViolation >= 0 && maxFreeSpaceViolation <= 1, s, "maxFreeSpaceViolation", "must be in [0, 1]");
	requireParam(wideAmbiguityMargin >= 0 && wideAmbiguityMargin <= 1, s, "wideAmbiguityMargin", "must be in [0, 1]");
}

}  // namespace lrgc
