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
	p.save_interval_s = lrgc::readDouble(source, section, "save_interval_s", save_interval_s);
	p.status_interval_s =
		lrgc::readDouble(source, section, "status_interval_s", status_interval_s);
	p.max_backlog_scans =
		lrgc::readCount(source, section, "max_backlog_scans", max_backlog_scans);
	p.sensor_timeout_s =
		lrgc::readDouble(source, section, "sensor_timeout_s", sensor_timeout_s);
	p.retry_initial_s = lrgc::readDouble(source, section, "retry_initial_s", retry_initial_s);
	p.retry_max_s = lrgc::readDouble(source, section, "retry_max_s", retry_max_s);
	p.loop_results_when_ready =
		lrgc::readBool(source, section, "loop_results_when_ready", loop_results_when_ready);
	lrgc::requireParam(p.save_interval_s >= 0, section, "save_interval_s", "must be >= 0");
	lrgc::requireParam(p.status_interval_s > 0, section, "status_interval_s", "must be > 0");
	lrgc::requireParam(p.sensor_timeout_s > 0, section, "sensor_timeout_s", "must be > 0");
	lrgc::requireParam(p.retry_initial_s > 0, section, "retry_initial_s", "must be > 0");
	lrgc::requireParam(p.retry_max_s >= p.retry_initial_s, section, "retry_max_s",
					   "must be >= retry_initial_s");
	*this = p;
}

void TLiveMappingParams::saveToConfigFile(mrpt::config::CConfigFileBase& target,
										  const std::string& section) const
{
	writeValue(target, section, "save_interval_s", save_interval_s,
			   "Save all maps every this many seconds of a live run [s]; 0: only at the end");
	writeValue(target, section, "status_interval_s", status_interval_s,
			   "Live status line period when stderr is not a terminal [s]");
	writeValue(target, section, "max_backlog_scans", uint64_t(max_backlog_scans),
			   "Scans waiting for the mapper before it skips some to keep up (capture keeps "
			   "all); 0: never skip");
	writeValue(target, section, "sensor_timeout_s", sensor_timeout_s,
			   "A sensor with no valid observation for this long is restarted [s]");
	writeValue(target, section, "retry_initial_s", retry_initial_s,
			   "First wait before restarting a failed sensor; doubles on each failure [s]");
	writeValue(target, section, "retry_max_s", retry_max_s,
			   "Longest wait between sensor restarts [s]");
	writeValue(target, section, "loop_results_when_ready", loop_results_when_ready,
			   "Apply loop-closing results as soon as ready: the robot never waits (false: "
			   "as offline, so mapping the capture offline gives the same map)");
}

}  // namespace lrgc::apps
