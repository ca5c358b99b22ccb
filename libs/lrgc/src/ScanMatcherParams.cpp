/* TScanMatcherParams: load / save / validate of section [ScanMatcher]. The key set is defined
 * by saveToConfigFile(); loadFromConfigFile() rejects any other key (params_io.h). */
#include <lrgc/ScanMatcher.h>
#include <lrgc/params_io.h>
#include <mrpt/config/CConfigFileBase.h>

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
	d.validate(s);
	*this = d;
}

void TScanMatcherParams::saveToConfigFile(
	mrpt::config::CConfigFileBase& c, const std::string& s) const
{
	const int nw = 26, vw = 12;
	c.write(s, "maxIterations", maxIterations, nw, vw, "Gauss-Newton iterations before 'no convergence'");
	c.write(s, "maxCorrespondenceDist_m", maxCorrespondenceDist_m, nw, vw, "[m] initial correspondence gate (shrinks to a few residual sigmas)");
	c.write(s, "refResolution_m", refResolution_m, nw, vw, "[m] voxel size reducing the reference points");
	c.write(s, "normalRadius_m", normalRadius_m, nw, vw, "[m] neighbourhood radius of the reference line fits (widened x4 where sparse)");
	c.write(s, "minInlierFraction", minInlierFraction, nw, vw, "[0..1] of the scan points; fewer inliers: no match");
	c.write(s, "minInliers", minInliers, nw, vw, "absolute minimum of inlier points; fewer: no match");
	c.write(s, "maxRmsResidual_m", maxRmsResidual_m, nw, vw, "[m] inlier RMS residual above it: no match");
	c.write(s, "minResidualStd_m", minResidualStd_m, nw, vw, "[m] floor of the residual scale estimated from the data");
	c.write(s, "unobservableStd_m", unobservableStd_m, nw, vw, "[m] std reported along directions the scans leave free (corridor axis)");
	c.write(s, "wideSearchStep_deg", wideSearchStep * 180 / M_PI, nw, vw, "[deg] heading step between matchWide's starting guesses");
	c.write(s, "wideAmbiguityMargin", wideAmbiguityMargin, nw, vw, "[0..1] matchWide: inlier fraction lead needed over a distinct alternative");
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
	requireParam(wideAmbiguityMargin >= 0 && wideAmbiguityMargin <= 1, s, "wideAmbiguityMargin", "must be in [0, 1]");
}

}  // namespace lrgc
