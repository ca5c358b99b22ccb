/* Section [RevisitLinker]: the parameters of CRevisitLinker, apart from the class so that the
 * map builder's public header (MapBuilderParams.h) needs none of the stage's internals. */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/core/bits_math.h>

#include <cmath>
#include <cstddef>
#include <string>

namespace lrgc
{
struct TRevisitLinkerParams : public mrpt::config::CLoadableOptions
{
	bool enabled = true;  //!< run the sweep at the end of the run (loop closing on)
	/** [m] old keyframes this close to k are candidates (1 m missed a lap driven 1 m beside
	 * the first; 3 m linked scans of another place: doc/parameters.md). */
	double radius_m = 2.0;
	double max_phi = mrpt::DEG2RAD(45.0);  //!< [rad] (key max_phi_deg)
	/** j < k - min_index_gap (beyond the local window, K = 15). 40 hid a sparse log's
	 * dead-end returns (keyframes 1 m apart: 40 m of path); on the dense logs the path
	 * condition below rules (their 40 keyframes span 14-17 m). */
	size_t min_index_gap = 15;
	/** [m] and j lies at least this much path (the straight steps between consecutive
	 * keyframes summed) before k; 0: no path condition. 15 kept a false link on sparse
	 * ACES (a dead-end return 15.5 m of path back, 0.31 m off along its corridor), 20 did
	 * not and closed as many places (doc/generalisation.md). */
	double min_path_gap_m = 20.0;
	/** A keyframe with no candidate within max_phi_deg, but old keyframes within radius_m
	 * facing another way (a corridor driven back), is matched against all the old keyframes
	 * within 3 radius_m, whatever their heading: a 180 deg laser sees the other half of the
	 * world, so one old scan shares only the side walls with it (sparse Killian's
	 * corridors driven back: doc/generalisation.md). */
	bool any_heading = true;
	size_t stride = 2;  //!< every stride-th keyframe is tried
	/** A match is kept only if k's patch (k +- this many keyframes, placed by the map),
	 * matched against the old keyframes near k, agrees with it (RevisitLinker.h); 0: no
	 * second match. */
	size_t patch_check_keyframes = 2;
	/** A match is kept only if no other local optimum within the prior explains as much of
	 * the scan (RevisitLinker.cpp, rivalFrom). */
	bool ambiguity_check = true;
	/** [rad] (key max_heading_std_deg) A match whose heading at its own position (the
	 * heading's std with the translation held: 1 / sqrt(Omega_phiphi) of the match's
	 * information) is looser than this matched no wall and is refused (RevisitLinker.cpp,
	 * fixesItsHeading); 0: no bound. True links on the sparse and harsh logs: under 0.75 deg;
	 * the two false ones of harsh Intel b80: 2.3-7.8 deg (doc/generalisation.md). */
	double max_heading_std = mrpt::DEG2RAD(1.5);
	/** A same-heading candidate is matched against the old keyframe's scan alone; where that
	 * fails and at least region_min_isolated_share of that scan's reduced points are isolated
	 * returns (no line and too few neighbours: a long-range laser's far walls, one return a
	 * metre at 60 m), it is matched again against the old map's region, every old keyframe
	 * within 3 radius_m, as an any-heading candidate is (RevisitLinker.h). */
	bool region_retry = true;
	/** [0..1] Session 65: 0.25 leaves the four dense and four sparse logs byte for byte and
	 * closes every revisited place of the glass atrium (doc/generalisation.md). */
	double region_min_isolated_share = 0.25;
	double min_inlier_fraction = 0.5;  //!< least fraction of k's points matched
	double gate_chi2 = 16.27;          //!< [chi2, 3 dof] agreement of the match with the guess
	double prior_std_xy_m = 0.3;       //!< [m] std of the guess (loop-closed map)
	double prior_std_phi = mrpt::DEG2RAD(3.0);  //!< [rad] (key prior_std_phi_deg)

	void loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
							const std::string& s) override;
	void saveToConfigFile(mrpt::config::CConfigFileBase& c,
						  const std::string& s) const override;
};

}  // namespace lrgc
