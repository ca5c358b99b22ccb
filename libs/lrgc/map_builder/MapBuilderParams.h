/* Parameters of CMetricMapBuilderLRGC: its own [MapBuilder] section and one section per
 * algorithm stage, loaded from and saved to an .ini in MRPT's way. An unknown section in an
 * lrgc .ini, or an unknown key in a known one, is an error. */
#pragma once

#include <lrgc/local_registration/LocalRegistrationParams.h>
#include <lrgc/common/params_io.h>
#include <lrgc/local_registration/MotionPredictorParams.h>
#include <lrgc/local_registration/SweepEstimatorParams.h>
#include <lrgc/map_builder/KeyframeReuseParams.h>
#include <lrgc/loop_closing/LoopCloserParams.h>
#include <lrgc/loop_closing/PatchCorrelatorParams.h>
#include <lrgc/loop_closing/RevisitLinkerParams.h>
#include <lrgc/pose_graph/PoseGraphOptimizerParams.h>
#include <lrgc/scan_matching/ScanMatcherParams.h>
#include <mrpt/config/CLoadableOptions.h>

#include <string>
#include <vector>

namespace lrgc
{
struct TMapBuilderParams : public mrpt::config::CLoadableOptions
{
	double keyframe_distance_m =
		0.3;  //!< [m] new keyframe after this much travel (paper: 0.3 m)
	double keyframe_angle =
		mrpt::DEG2RAD(15.0);  //!< [rad] or this much turn (key keyframe_angle_deg)
	size_t min_scan_points =
		20;  //!< scans with fewer valid returns are skipped, with a warning
	double grid_resolution_m = 0.05;  //!< [m] cell size of the exported occupancy grid
	bool loop_closing = true;  //!< global correlation and loop closing (false: local only)
	bool final_optimization = true;  //!< optimise the whole graph at the end of the run
	/** [s] time from the laser's first beam to its last (SICK LMS 2xx, 180 deg: 6.7 ms);
	 * scans are de-skewed by the predicted motion over it (Scan.h); 0: no de-skewing, or
	 * estimated online if [SweepEstimator] enabled (off by default: doc/scan-matching.md) */
	double scan_sweep_time_s = 0.0;
	/** The laser (CObservation2DRangeScan::sensorLabel) the map is built from, e.g. "LASER"
	 * (a CARMEN log's FLASER) or "REAR_LASER" (RLASER); empty: the first one seen. Scans of
	 * other lasers are counted and ignored (CLaserSelector). */
	std::string laser_label;
	double min_range_m =
		0.0;  //!< [m] the mapped laser's readings below are dropped (own posts); 0: none
	double max_range_m = 0.0;  //!< [m] ... and above; 0: only the sensor's own maximum range

	void loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
							const std::string& s) override;
	void saveToConfigFile(mrpt::config::CConfigFileBase& c,
						  const std::string& s) const override;
};

/** Every parameter of the LRGC pipeline, one .ini section per stage. */
struct TLRGCParams : public mrpt::config::CLoadableOptions
{
	TMapBuilderParams builder;            //!< [MapBuilder]
	TKeyframeReuseParams reuse;           //!< [KeyframeReuse]
	TMotionPredictorParams motion;        //!< [MotionPredictor]
	TSweepEstimatorParams sweep;          //!< [SweepEstimator]
	TScanMatcherParams matcher;           //!< [ScanMatcher]
	TLocalRegistrationParams local;       //!< [LocalRegistration]
	TPoseGraphOptimizerParams optimizer;  //!< [PoseGraphOptimizer]
	TLoopCloserParams loop;               //!< [LoopCloser]
	TPatchCorrelatorParams correlator;    //!< [PatchCorrelator]
	TRevisitLinkerParams revisits;        //!< [RevisitLinker]

	/** Loads every stage's section. `section` is a prefix of every stage's section name, so
	 * that one .ini can hold lrgc's sections beside another program's: "" reads [MapBuilder],
	 * [ScanMatcher], ...; "lrgc." reads [lrgc.MapBuilder], [lrgc.ScanMatcher], ... Other
	 * sections are left to the caller, who checks them against sectionNames(). Keys of an
	 * earlier lrgc (renamedKeys()) are read under their new names; their warnings go to
	 * stderr (loadReportingRenames() returns them instead). */
	void loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
							const std::string& section = {}) override;
	/** As loadFromConfigFile(), returning one warning per old key name read. */
	std::vector<std::string> loadReportingRenames(const mrpt::config::CConfigFileBase& c,
												  const std::string& section = {});
	/** Saves every stage's section, each name prefixed by `section` (as loadFromConfigFile). */
	void saveToConfigFile(mrpt::config::CConfigFileBase& c,
						  const std::string& section = {}) const override;
	/** The .ini sections of the stages (without a prefix), in the order they are saved. */
	static const std::vector<std::string>& sectionNames();
	/** The keys of the stages' sections renamed since an earlier lrgc (still read). */
	static const std::vector<TRenamedKey>& renamedKeys();
};

/** Throws naming the first section of `c` that is not in `allowed` (a misspelt section
 * would otherwise be silently ignored). */
void rejectUnknownSections(const mrpt::config::CConfigFileBase& c,
						   const std::vector<std::string>& allowed);

}  // namespace lrgc
