/* Options of `lrgc-slam --live` (section [LiveMapping] of the lrgc .ini): how often maps are
 * saved and the status line is printed, how mapping keeps up when it falls behind, and how a
 * silent or failing sensor is restarted. The sensors themselves are described by the
 * rawlog-grabber .ini given to --live (see doc/live.md); these keys are about the run.
 *
 * Keep-up policy (CKeepUpPolicy in live/KeepUpPolicy.h): while more than max_backlog_scans
 * laser scans wait for the mapper, it maps one scan and then skips floor(waiting /
 * max_backlog_scans) waiting scans. Odometry is never skipped and the capture keeps every scan.
 * Restart policy (CSensorSupervisor): a driver that throws, or delivers no valid observation
 * for sensor_timeout_s, is destroyed and started again after a back-off that doubles from
 * retry_initial_s up to retry_max_s, and goes back to retry_initial_s once data flows.
 */
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <cstddef>

namespace lrgc::apps
{
struct TLiveMappingParams : public mrpt::config::CLoadableOptions
{
	double save_interval_s = 60;   //!< [s] periodic save of all maps; 0: only at the end
	double status_interval_s = 2;  //!< [s] status line period when stderr is not a terminal
	/** Laser scans allowed to wait for the mapper before it skips scans; 0: never skip (the
	 * backlog may then grow without bound, and a stop waits until it is mapped). */
	size_t max_backlog_scans = 20;
	double sensor_timeout_s = 3;   //!< [s] no valid observation this long: restart driver
	double retry_initial_s = 0.5;  //!< [s] first back-off before restarting a sensor
	double retry_max_s = 30;       //!< [s] longest back-off
	/** Apply a loop search's result as soon as the worker has it, so the robot never waits
	 * (TLoopCloserParams::apply_when_ready for this run), and with --localize a global
	 * search's (CLocalizer::setResultsWhenReady); false: at the fixed keyframe or scan as
	 * offline runs do, so that the capture run offline gives the same map or poses. */
	bool loop_results_when_ready = true;

	/** Reads the keys of `section`; unknown keys and invalid values throw. */
	void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
							const std::string& section) override;
	void saveToConfigFile(mrpt::config::CConfigFileBase& target,
						  const std::string& section) const override;
};

}  // namespace lrgc::apps
