/* Section [ScanMatcher]: the parameters of CScanMatcher, apart from the class so that the
 * map builder's public header (MapBuilderParams.h) needs none of the stage's internals. */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/core/bits_math.h>

#include <cmath>
#include <cstddef>
#include <string>

namespace lrgc
{
/** Section [ScanMatcher]. */
struct TScanMatcherParams : public mrpt::config::CLoadableOptions
{
	int max_iterations = 50;  //!< Gauss-Newton iterations before giving up (no convergence)
	double max_correspondence_dist_m = 0.5;  //!< [m] initial gate: farther pairs are not formed
	double ref_resolution_m = 0.02;  //!< [m] voxel size for reducing the reference points
	double normal_radius_m = 0.15;   //!< [m] neighbourhood radius of the local line fits
	/** [rad] (key far_fit_angle_deg) The far fit: a point whose neighbourhoods up to 4
	 * normal_radius_m hold no line is fitted once more within range x this (range from the
	 * reference frame's origin, the sensor of a scan, the newest keyframe of a patch), up to
	 * far_fit_max_radius_m, where that is wider. A long-range laser samples a wall at range r
	 * every r x (beam spacing): 1 m at 60 m for a 1-degree laser, so its far walls are
	 * isolated returns, never matched, without it. 0: off, the default: at 3 deg the sparse
	 * logs and the crowded hall improve, but a glass atrium's map breaks (lines fitted through
	 * returns from behind the panes) and three e2e tests fail (doc/generalisation.md, "The
	 * far fit"). */
	double far_fit_angle = 0;
	double far_fit_max_radius_m = 4.0;  //!< [m] the far fit's widest neighbourhood
	double min_inlier_fraction = 0.25;  //!< of the scan's points, below it: no match
	int min_inliers = 20;               //!< absolute minimum of inlier points
	double max_rms_residual_m = 0.1;    //!< [m] inlier RMS residual above it: no match
	double min_residual_std_m = 0.003;  //!< [m] floor of the estimated residual scale
	/** Of the scan points lying where the reference's beams passed (free space); above it: no
	 * match. Used by loop closing and revisits; local registration matches with its own
	 * [LocalRegistration] max_free_space_violation instead. */
	double max_free_space_violation = 0.15;
	/** [m] The free-space check counts only runs of violating scan points this long
	 * (CScanViolation::share); 0: every violating point with a violating neighbour. Not a
	 * [ScanMatcher] key: local registration sets it for some plain matches
	 * ([LocalRegistration] crowd_min_run_m). */
	double free_space_min_run_m = 0;
	double unobservable_std_m = 1.0;  //!< [m] std reported along directions the data do not fix
	double wide_search_step = 7.5 * M_PI / 180;  //!< [rad] matchWide's heading step (key _deg)
	/** matchWide: lead the winner needs over every distinct alternative and over the guess's
	 * own optimum, in share of the scan's points within max_rms_residual_m of the reference. */
	double wide_ambiguity_margin = 0.15;
	/** matchWide: the winner must match at least this fraction of the scan's points. True
	 * glitch recoveries on the benchmark logs match 53-90 %; a false 108-deg "recovery" on
	 * Intel matched 29 % (issue 11); a true 80-deg turn among a museum's visitors 43.8 %
	 * (0.45 until session 64: MuseumSparse, doc/generalisation.md). */
	double wide_min_inlier_fraction = 0.40;

	void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
							const std::string& section) override;
	void saveToConfigFile(mrpt::config::CConfigFileBase& target,
						  const std::string& section) const override;
	/** Throws (naming section and key) if a value is out of range. */
	void validate(const std::string& section = "ScanMatcher") const;
};

}  // namespace lrgc
