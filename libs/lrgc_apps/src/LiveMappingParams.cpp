#include "LiveMappingParams.h"

#include <lrgc/common/params_io.h>
#include <mrpt/config/CConfigFileBase.h>

namespace lrgc::apps
{
void TLiveMappingParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
											const std::string& section)
{
	lrgc::rejectUnknownKeys(*this, source, section);
	TLiveMappingParams p = *this;
	p.saveIntervalSeconds =
		lrgc::readDouble(source, section, "save_interval_s", saveIntervalSeconds);
	p.statusIntervalSeconds =
		lrgc::readDouble(source, section, "status_interval_s", statusIntervalSeconds);
	p.maxBacklogScans = lrgc::readCount(source, section, "max_backlog_scans", maxBacklogScans);
	p.sensorTimeoutSeconds =
		lrgc::readDouble(source, section, "sensor_timeout_s", sensorTimeoutSeconds);
	p.retryInitialSeconds =
		lrgc::readDouble(source, section, "retry_initial_s", retryInitialSeconds);
	p.retryMaxSeconds = lrgc::readDouble(source, section, "retry_max_s", retryMaxSeconds);
	p.loopResultsWhenReady =
		lrgc::readBool(source, section, "loop_results_when_ready", loopResultsWhenReady);
	lrgc::requireParam(p.saveIntervalSeconds >= 0, section, "save_interval_s", "must be >= 0");
	lrgc::requireParam(p.statusIntervalSeconds > 0, section, "status_interval_s",
					   "must be > 0");
	lrgc::requireParam(p.sensorTimeoutSeconds > 0, section, "sensor_timeout_s", "must be > 0");
	lrgc::requireParam(p.retryInitialSeconds > 0, section, "retry_initial_s", "must be > 0");
	lrgc::requireParam(p.retryMaxSeconds >= p.retryInitialSeconds, section, "retry_max_s",
					   "must be >= retry_initial_s");
	*this = p;
}

void TLiveMappingParams::saveToConfigFile(mrpt::config::CConfigFileBase& target,
										  const std::string& section) const
{
	target.write(section, "save_interval_s", saveIntervalSeconds, -1, -1,
				 "Save all maps every this many seconds of a live run [s]; 0: only at the end");
	target.write(section, "status_interval_s", statusIntervalSeconds, -1, -1,
				 "Live status line period when stderr is not a terminal [s]");
	target.write(section, "max_backlog_scans", static_cast<int>(maxBacklogScans), -1, -1,
				 "Scans waiting for the mapper before it skips some to keep up (capture keeps "
				 "all); 0: never skip");
	target.write(section, "sensor_timeout_s", sensorTimeoutSeconds, -1, -1,
				 "A sensor with no valid observation for this long is restarted [s]");
	target.write(section, "retry_initial_s", retryInitialSeconds, -1, -1,
				 "First wait before restarting a failed sensor; doubles on each failure [s]");
	target.write(section, "retry_max_s", retryMaxSeconds, -1, -1,
				 "Longest wait between sensor restarts [s]");
	target.write(section, "loop_results_when_ready", loopResultsWhenReady, -1, -1,
				 "Apply loop-closing results as soon as ready: the robot never waits (false: "
				 "as offline, so mapping the capture offline gives the same map)");
}

}  // namespace lrgc::apps
