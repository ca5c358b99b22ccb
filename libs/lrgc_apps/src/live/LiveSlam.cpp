/* CLiveSlam::run: the live run's threads, stop sequence and live.json. */
#include "lrgc_apps/live/LiveSlam.h"

#include "lrgc_apps/SlamApp.h"
#include "lrgc_apps/atomic_file.h"
#include "lrgc_apps/live/CaptureWriter.h"
#include "lrgc_apps/live/LiveConsole.h"
#include "lrgc_apps/live/LiveMapper.h"
#include "lrgc_apps/live/LiveQueues.h"
#include "lrgc_apps/live/SensorSupervisor.h"
#include "lrgc_apps/live/StopSignalWatcher.h"

#include <mrpt/config/CConfigFile.h>
#include <mrpt/core/format.h>

#include <atomic>
#include <csignal>
#include <filesystem>
#include <memory>
#include <mutex>
#include <sstream>
#include <thread>

namespace lrgc::apps
{
namespace
{
using namespace std::chrono_literals;
using TSensors = std::vector<std::unique_ptr<CSensorSupervisor>>;

std::string jsonString(const std::string& s)
{
	std::string out = "\"";
	for (const char ch : s)
	{
		if (ch == '"' || ch == '\\')
			out += '\\', out += ch;
		else if (static_cast<unsigned char>(ch) < 0x20)
			out += mrpt::format("\\u%04x", static_cast<unsigned>(ch));
		else
			out += ch;
	}
	return out + "\"";
}

std::string liveJson(const std::string& status, const std::string& sensorsIni,
					 const CCaptureWriter& capture, const CLiveQueues& queues,
					 const CLiveMapper& mapper, const TSensors& sensors)
{
	const TLiveMapperCounts& m = mapper.counts();
	const TLatencySummary lat = summarizeLatencies(mapper.queueLatencyMs());
	std::ostringstream j;
	j << "{\n"
	  << "  \"status\": " << jsonString(status) << ",\n"
	  << "  \"sensors_ini\": " << jsonString(sensorsIni) << ",\n"
	  << "  \"capture\": {\"file\": \"capture.rawlog\", \"objects\": " << capture.objects()
	  << ", \"bytes\": " << capture.bytes() << "},\n"
	  << "  \"received\": {\"objects\": " << queues.pushed()
	  << ", \"scans\": " << queues.scansPushed() << "},\n"
	  << "  \"mapping\": {\"objects_taken\": " << m.items << ", \"scans_taken\": " << m.scans
	  << ", \"scans_mapped\": " << m.scansMapped
	  << ", \"skipped_to_keep_up\": " << mapper.policy().skippedTotal()
	  << ", \"odometry\": " << m.odometry << ", \"other_observations\": " << m.otherObservations
	  << ", \"not_observations\": " << m.notObservations << ", \"saves\": " << m.saves
	  << mrpt::format(
			 ", \"queue_latency_ms\": {\"median\": %.3f, \"p99\": %.3f, \"max\": %.3f}},\n",
			 lat.median_ms, lat.p99_ms, lat.max_ms)
	  << "  \"sensors\": [";
	for (size_t i = 0; i < sensors.size(); ++i)
	{
		const TSensorSection& s = sensors[i]->sensor();
		const TSensorCounters c = sensors[i]->counters();
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

/** The first fatal error of the run (capture or mapping), set from any thread. */
class CFatal
{
public:
	void set(const std::string& why)
	{
		std::lock_guard<std::mutex> lock(m_mutex);
		if (m_why.empty()) m_why = why;
		m_set = true;
	}
	bool isSet() const { return m_set; }
	std::string why() const
	{
		std::lock_guard<std::mutex> lock(m_mutex);
		return m_why;
	}

private:
	mutable std::mutex m_mutex;
	std::atomic<bool> m_set{false};
	std::string m_why;
};

/** The capture writer's thread body: everything queued goes to disk, in order, until the
 * intake is closed and drained. After a write error the rest is drained and dropped. */
void captureLoop(CLiveQueues& queues, CCaptureWriter& capture, CFatal& fatal)
{
	bool failed = false;
	while (true)
	{
		const std::vector<TLiveItem> items = queues.takeForCapture(200ms);
		for (const TLiveItem& it : items)
		{
			if (failed) break;
			try
			{
				capture.append(*it.object);
			}
			catch (const std::exception& e)
			{
				failed = true;
				fatal.set("capture: " + shortError(e));
			}
		}
		if (items.empty() && queues.closed()) return;
	}
}

std::string statusLine(const CLiveQueues& queues, const CLiveMapper& mapper,
					   const TSensors& sensors)
{
	std::string line = mrpt::format(
		"live: received %llu scans, mapped %zu, queue %zu, loops %zu, skipped %zu |",
		static_cast<unsigned long long>(queues.scansPushed()), mapper.counts().scansMapped,
		queues.mappingDepth(), mapper.builder().stats().loopClosures,
		mapper.policy().skippedTotal());
	for (const auto& s : sensors) line += " " + s->sensor().section + " " + s->counters().state;
	return line;
}
}  // namespace

int CLiveSlam::run(const std::function<bool()>& stop)
{
	namespace fs = std::filesystem;
	const TSensorRig rig = loadSensorRig(m_setup.sensorsIni);
	const TLiveMappingParams& lp = m_setup.config.live;
	fs::create_directories(m_setup.outDir);
	const std::string capturePath = (fs::path(m_setup.outDir) / "capture.rawlog").string();
	if (fs::exists(capturePath))
		throw CUsageError("'" + capturePath +
						  "' exists: a live run never overwrites a capture; choose " +
						  "another --out DIR or move the file");
	CCaptureWriter capture(capturePath);
	const mrpt::config::CConfigFile ini(m_setup.sensorsIni);
	CLiveConsole console(m_err, m_setup.quiet, lp.statusIntervalSeconds);
	for (const auto& note : rig.notes) console.message("live: " + note, false);

	// A socket driver writing to a peer that went away must get EPIPE, not kill the process.
	const auto oldSigpipe = std::signal(SIGPIPE, SIG_IGN);
	CLiveQueues queues;
	CLiveMapper mapper(m_setup.config, m_setup.outDir, m_setup.sensorsIni, console);
	CFatal fatal;
	std::thread writer([&] { captureLoop(queues, capture, fatal); });
	TSensors sensors;
	for (const TSensorSection& s : rig.sensors)
		sensors.push_back(std::make_unique<CSensorSupervisor>(
			ini, s, lp,
			[&queues, section = s.section](const auto& obj)
			{ return queues.push(section, obj); },
			[&console](const std::string& line, bool important)
			{ console.message(line, important); }));
	for (auto& s : sensors) s->start();
	console.message(
		mrpt::format(
			"live: %zu sensor(s) from %s; capture: %s; maps saved %s and at the end; Ctrl-C "
			"stops",
			sensors.size(), m_setup.sensorsIni.c_str(), capturePath.c_str(),
			lp.saveIntervalSeconds > 0
				? mrpt::format("every %g s", lp.saveIntervalSeconds).c_str()
				: "only on stop"),
		false);

	bool closing = false, mappingFailed = false;
	auto lastSave = std::chrono::steady_clock::now();
	while (true)
	{
		if (!closing && (stop() || fatal.isSet()))
		{
			closing = true;
			queues.close();
			for (auto& s : sensors) s->requestStop();
			console.message(
				mrpt::format(
					"live: stopping: mapping the %zu queued observation(s), then saving "
					"(Ctrl-C "
					"again exits at once; the capture and the last saved maps stay valid)",
					queues.mappingDepth()),
				true);
		}
		size_t behind = 0;
		const std::optional<TLiveItem> item = queues.takeForMapping(100ms, &behind);
		if (!item && closing) break;
		if (item && !mappingFailed)
		{
			try
			{
				mapper.process(*item, behind);
			}
			catch (const std::exception& e)
			{
				mappingFailed = true;
				fatal.set("mapping: " + shortError(e));
			}
		}
		console.status(statusLine(queues, mapper, sensors));
		const auto now = std::chrono::steady_clock::now();
		if (!closing && lp.saveIntervalSeconds > 0 &&
			std::chrono::duration<double>(now - lastSave).count() >= lp.saveIntervalSeconds &&
			mapper.builder().stats().scans > 0)
		{
			lastSave = now;
			try
			{
				capture.sync();
				mapper.save("running (periodic save)");
				writeTextFileAtomically(
					(fs::path(m_setup.outDir) / "live.json").string(),
					liveJson("running", m_setup.sensorsIni, capture, queues, mapper, sensors));
				console.message(
					mrpt::format(
						"live: maps saved (%zu scans, %zu keyframes) in %.2f s",
						mapper.builder().stats().scans, mapper.builder().stats().keyframes,
						std::chrono::duration<double>(std::chrono::steady_clock::now() - now)
							.count()),
					false);
			}
			catch (const std::exception& e)
			{
				console.message("live: periodic save failed: " + shortError(e), true);
			}
		}
	}
	console.status(statusLine(queues, mapper, sensors), true);
	console.endStatus();

	writer.join();
	try
	{
		capture.close();
	}
	catch (const std::exception& e)
	{
		fatal.set("capture: " + shortError(e));
	}
	const std::string status = fatal.isSet() ? "error: " + fatal.why() : "stopped on request";
	int exitCode = fatal.isSet() ? kExitInputError : kExitOk;
	try
	{
		if (!mappingFailed) mapper.finish();
		mapper.save(status);
	}
	catch (const std::exception& e)
	{
		console.message("live: saving the final maps failed: " + shortError(e), true);
		exitCode = kExitInputError;
	}
	const std::string liveJsonPath = (fs::path(m_setup.outDir) / "live.json").string();
	writeTextFileAtomically(
		liveJsonPath, liveJson(status, m_setup.sensorsIni, capture, queues, mapper, sensors));
	console.message(
		"live: maps saved; waiting for the sensor drivers to return from their current call",
		false);
	for (auto& s : sensors) s->join();
	writeTextFileAtomically(
		liveJsonPath, liveJson(status, m_setup.sensorsIni, capture, queues, mapper, sensors));
	std::signal(SIGPIPE, oldSigpipe);

	const auto& st = mapper.builder().stats();
	if (fatal.isSet())
		console.message("lrgc-slam: " + status + " (what was mapped is saved)", true);
	console.message(
		mrpt::format(
			"lrgc-slam: live run %s: %llu scans received (%llu objects captured), %zu mapped, "
			"%zu skipped to keep up, %zu keyframes, %zu loop closures; outputs in %s",
			fatal.isSet() ? "failed" : "stopped",
			static_cast<unsigned long long>(queues.scansPushed()),
			static_cast<unsigned long long>(capture.objects()), mapper.counts().scansMapped,
			mapper.policy().skippedTotal(), st.keyframes, st.loopClosures,
			m_setup.outDir.c_str()),
		fatal.isSet());
	return exitCode;
}

int runLiveSlam(const TSlamCommandLine& cl, std::FILE* err)
{
	TLiveSlamSetup setup;
	setup.sensorsIni = cl.live;
	setup.config = loadAppConfig(cl.config);
	setup.outDir = cl.outDir;
	setup.quiet = cl.quiet;
	const CStopSignalWatcher signals;  // before the run's threads, which inherit its mask
	return CLiveSlam(std::move(setup), err).run([&] { return signals.stopRequested(); });
}

}  // namespace lrgc::apps
