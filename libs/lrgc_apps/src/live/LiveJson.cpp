/* live.json (see LiveJson.h). */
#include "live/LiveJson.h"

#include "lrgc_apps/RunOutputs.h"
#include "lrgc_apps/RunStats.h"
#include "live/CaptureWriter.h"
#include "live/LiveQueues.h"

#include <mrpt/core/format.h>

#include <sstream>

namespace lrgc::apps
{
TLiveJsonState liveState(const std::string& status, const std::string& sensorsIni,
						 const CCaptureWriter& capture, const CLiveQueues& queues,
						 const CLiveProcessor& processor, const TSupervisors& sensors)
{
	TLiveJsonState st;
	st.status = status;
	st.sensorsIni = sensorsIni;
	st.captureObjects = capture.objects();
	st.captureBytes = capture.bytes();
	st.pushed = queues.pushed();
	st.scansPushed = queues.scansPushed();
	st.counts = processor.counts();
	st.skipped = processor.policy().skippedTotal();
	st.queueLatency = processor.queueLatency().summary();
	for (const auto& s : sensors) st.sensors.emplace_back(s->sensor(), s->counters());
	return st;
}

std::string liveJson(const TLiveJsonState& st)
{
	const TLiveMapperCounts& m = st.counts;
	const TLatencySummary& lat = st.queueLatency;
	std::ostringstream j;
	j << "{\n"
	  << "  \"status\": " << jsonString(st.status) << ",\n"
	  << "  \"sensors_ini\": " << jsonString(st.sensorsIni) << ",\n"
	  << "  \"capture\": {\"file\": \"capture.rawlog\", \"objects\": " << st.captureObjects
	  << ", \"bytes\": " << st.captureBytes << "},\n"
	  << "  \"received\": {\"objects\": " << st.pushed << ", \"scans\": " << st.scansPushed
	  << "},\n"
	  << "  \"mapping\": {\"objects_taken\": " << m.items << ", \"scans_taken\": " << m.scans
	  << ", \"scans_mapped\": " << m.scansMapped << ", \"skipped_to_keep_up\": " << st.skipped
	  << ", \"odometry\": " << m.odometry << ", \"other_observations\": " << m.otherObservations
	  << ", \"not_observations\": " << m.notObservations << ", \"saves\": " << st.saves
	  << mrpt::format(
			 ", \"queue_latency_ms\": {\"median\": %.3f, \"p99\": %.3f, \"max\": %.3f}},\n",
			 lat.median_ms, lat.p99_ms, lat.max_ms)
	  << "  \"sensors\": [";
	for (size_t i = 0; i < st.sensors.size(); ++i)
	{
		const auto& [s, c] = st.sensors[i];
		j << (i ? ",\n" : "\n") << "    {\"section\": " << jsonString(s.section)
		  << ", \"driver\": " << jsonString(s.driver) << ", \"label\": " << jsonString(s.label)
		  << ", \"state\": " << jsonString(c.state) << ", \"starts\": " << c.starts
		  << ", \"failures\": " << c.failures << ", \"observations\": " << c.observations
		  << ", \"scans\": " << c.scans << ", \"rejected_without_data\": " << c.rejected
		  << ", \"last_problem\": " << jsonString(c.lastProblem) << "}";
	}
	j << "\n  ]\n}\n";
	return j.str();
}

}  // namespace lrgc::apps
