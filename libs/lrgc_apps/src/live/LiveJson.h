/* live.json: what a live run reports beside its maps (doc/live.md, "Outputs"). The state is
 * copied on the mapping thread (liveState) so that the saver thread can write it (liveJson). */
#pragma once

#include "live/LiveProcessor.h"
#include "live/SensorSupervisor.h"

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace lrgc::apps
{
class CCaptureWriter;
class CLiveQueues;
using TSupervisors = std::vector<std::unique_ptr<CSensorSupervisor>>;

/** What live.json says, copied on the mapping thread so that the saver thread can write it. */
struct TLiveJsonState
{
	std::string status, sensorsIni;
	uint64_t captureObjects = 0, captureBytes = 0, pushed = 0, scansPushed = 0;
	TLiveMapperCounts counts;
	size_t skipped = 0;
	size_t saves = 0;              //!< saves written, this one included
	TLatencySummary queueLatency;  //!< [ms]
	std::vector<std::pair<TSensorSection, TSensorCounters>> sensors;
};

/** A copy of what live.json reports, taken now. */
TLiveJsonState liveState(const std::string& status, const std::string& sensorsIni,
						 const CCaptureWriter& capture, const CLiveQueues& queues,
						 const CLiveProcessor& processor, const TSupervisors& sensors);

/** live.json's text. */
std::string liveJson(const TLiveJsonState& state);

}  // namespace lrgc::apps
