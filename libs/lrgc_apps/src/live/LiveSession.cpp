/* CLiveSession: the live run's threads, stop sequence, saves and live.json. */
#include "live/LiveSession.h"

#include "SlamApp.h"
#include "atomic_file.h"
#include "live/LiveLocalizer.h"
#include "live/LiveMapper.h"

#include <mrpt/core/format.h>

#include <filesystem>

namespace lrgc::apps
{
namespace
{
using namespace std::chrono_literals;

/** [s] After the first signal, the computations still running are cut (DelayedStop.h). An
 * ordinary stop (the queue drained, mapping having kept up) takes well under a second. */
constexpr double kCutGraceSeconds = 3;

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
				fatal.set("capture: " + oneLineError(e));
			}
		}
		if (items.empty() && queues.closed()) return;
	}
}

std::string statusLine(const CLiveQueues& queues, const CLiveProcessor& processor,
					   const TSensors& sensors)
{
	std::string line = mrpt::format("live: received %llu scans, %s, skipped %zu |",
									static_cast<unsigned long long>(queues.scansPushed()),
									processor.statusText(queues.mappingDepth()).c_str(),
									processor.policy().skippedTotal());
	for (const auto& s : sensors) line += " " + s->sensor().section + " " + s->counters().state;
	return line;
}

/** What the run does with the observations: maps (perhaps continuing a saved map) or
 * localises on a saved map. */
std::unique_ptr<CLiveProcessor> processorFor(const TLiveSlamSetup& setup, CLiveConsole& console,
											 const CStopToken& cut)
{
	std::unique_ptr<CLiveProcessor> p;
	if (setup.localizeMap)
		p = std::make_unique<CLiveLocalizer>(setup.config, *setup.localizeMap, setup.outDir,
											 setup.sensorsIni, console);
	else
		p = std::make_unique<CLiveMapper>(setup.config, setup.outDir, setup.sensorsIni, console,
										  setup.initialMap ? &*setup.initialMap : nullptr);
	p->setStopToken(cut);
	return p;
}
}  // namespace

CLiveSession::CLiveSession(const TLiveSlamSetup& setup, const TSensorRig& rig, std::FILE* err,
						   TPeriodicSaveHook saveHook)
	: m_setup(setup),
	  m_saveHook(std::move(saveHook)),
	  m_params(setup.config.live),
	  m_capture(captureFileOf(setup.outDir)),
	  m_ini(setup.sensorsIni),
	  m_console(err, setup.quiet, m_params.status_interval_s),
	  m_cut(setup.cut, kCutGraceSeconds),
	  m_processor(processorFor(setup, m_console, m_cut.token()))
{
	for (const auto& note : rig.notes) m_console.message("live: " + note, false);
	m_writer = std::thread([this] { captureLoop(m_queues, m_capture, m_fatal); });
	for (const TSensorSection& s : rig.sensors)
		m_sensors.push_back(std::make_unique<CSensorSupervisor>(
			m_ini, s, m_params,
			[this, section = s.section](const auto& obj)
			{ return m_queues.push(section, obj); },
			[this](const std::string& line, bool important)
			{ m_console.message(line, important); }));
	for (auto& s : m_sensors) s->start();
	m_console.message(
		mrpt::format("live: %zu sensor(s) from %s; capture: %s; maps saved %s and at the end; "
					 "Ctrl-C stops",
					 m_sensors.size(), setup.sensorsIni.c_str(), m_capture.path().c_str(),
					 m_params.save_interval_s > 0
						 ? mrpt::format("every %g s", m_params.save_interval_s).c_str()
						 : "only on stop"),
		false);
}

CLiveSession::~CLiveSession()
{
	m_queues.close();  // on an exception: let the writer finish
	if (m_writer.joinable()) m_writer.join();
}

void CLiveSession::mapUntilStopped(const std::function<bool()>& stop)
{
	bool closing = false;
	auto lastSave = std::chrono::steady_clock::now();
	while (true)
	{
		if (!closing && (stop() || m_fatal.isSet()))
		{
			closing = true;
			beginStop();
		}
		size_t behind = 0;
		const std::optional<TLiveItem> item = m_queues.takeForMapping(100ms, &behind);
		if (!item && closing) break;
		if (item) mapItem(*item, behind);
		m_scansMapped = m_processor->counts().scansMapped;
		m_console.status(statusLine(m_queues, *m_processor, m_sensors));
		const auto now = std::chrono::steady_clock::now();
		if (!closing && m_params.save_interval_s > 0 &&
			std::chrono::duration<double>(now - lastSave).count() >= m_params.save_interval_s &&
			m_processor->anyScan() && periodicSave())
			lastSave = now;
	}
	m_console.status(statusLine(m_queues, *m_processor, m_sensors), true);
	m_console.endStatus();
}

int CLiveSession::finish()
{
	m_saver.waitIdle();  // a periodic save still running ends first (same files)
	m_writer.join();
	try
	{
		m_capture.close();
	}
	catch (const std::exception& e)
	{
		m_fatal.set("capture: " + oneLineError(e));
	}
	std::string silent = noSensorStarted();
	if (silent.empty()) silent = m_processor->failure();  // e.g. no start found
	const std::string status = m_fatal.isSet()  ? "error: " + m_fatal.why()
							   : silent.empty() ? "stopped on request"
												: silent;
	int exitCode = m_fatal.isSet() || !silent.empty() ? kExitInputError : kExitOk;
	try
	{
		if (!m_mappingFailed) m_processor->finish();
		writeSave(m_processor->saveJob(status), liveState(status));
	}
	catch (const std::exception& e)
	{
		m_console.message("live: saving the final maps failed: " + oneLineError(e), true);
		exitCode = kExitInputError;
	}
	m_console.message(
		"live: maps saved; waiting for the sensor drivers to return from their current "
		"call",
		false);
	for (auto& s : m_sensors) s->join();
	try
	{
		writeLiveJson(status);  // the sensors' final counts
	}
	catch (const std::exception&)
	{
		// The version written before the wait stands.
	}
	summary(status);
	return exitCode;
}

std::string CLiveSession::noSensorStarted() const
{
	std::string problems;
	for (const auto& s : m_sensors)
	{
		const TSensorCounters c = s->counters();
		if (c.starts > 0) return {};
		// "live: [LASER] CLMS100Eth cannot start: ...; retrying in 8 s" -> "[LASER] ...
		// ..."
		const std::string& p = c.lastProblem;
		const size_t from = std::min(p.find('['), p.size());
		problems += (problems.empty() ? "" : "; ") +
					(p.empty() ? "[" + s->sensor().section + "] never started"
							   : p.substr(from, p.rfind("; ") - from));
	}
	return "no sensor delivered data (" + problems + ")";
}

std::string CLiveSession::captureFileOf(const std::string& outDir)
{
	return (std::filesystem::path(outDir) / "capture.rawlog").string();
}

void CLiveSession::beginStop()
{
	m_queues.close();
	for (auto& s : m_sensors) s->requestStop();
	m_console.message(
		mrpt::format(
			"live: stopping: mapping the %zu queued observation(s), then saving (Ctrl-C "
			"again exits at once; the capture and the last saved maps stay valid)",
			m_queues.mappingDepth()),
		true);
}

void CLiveSession::mapItem(const TLiveItem& item, size_t behind)
{
	if (m_mappingFailed) return;  // drained without mapping: the capture gets it all
	try
	{
		m_processor->process(item, behind);
	}
	catch (const std::exception& e)
	{
		m_mappingFailed = true;
		m_fatal.set("mapping: " + oneLineError(e));
	}
}

bool CLiveSession::periodicSave()
{
	if (!m_saver.idle()) return false;
	auto job = m_processor->saveJob("running (periodic save)");
	auto live = std::make_shared<const TLiveJsonState>(liveState("running"));
	return m_saver.trySubmit(
		[this, job, live]
		{
			const auto t0 = std::chrono::steady_clock::now();
			try
			{
				if (m_saveHook) m_saveHook([this] { return m_scansMapped.load(); });
				m_capture.sync();
				const std::string what = writeSave(job, *live);
				m_console.message(mrpt::format("live: %s in %.2f s", what.c_str(),
											   std::chrono::duration<double>(
												   std::chrono::steady_clock::now() - t0)
												   .count()),
								  false);
			}
			catch (const std::exception& e)
			{
				m_console.message("live: periodic save failed: " + oneLineError(e), true);
			}
		});
}

std::string CLiveSession::writeSave(const std::function<std::string()>& job,
									TLiveJsonState live)
{
	const std::string what = job();
	live.saves = ++m_saves;
	writeLiveJson(live);
	return what;
}

TLiveJsonState CLiveSession::liveState(const std::string& status) const
{
	return lrgc::apps::liveState(status, m_setup.sensorsIni, m_capture, m_queues, *m_processor,
								 m_sensors);
}

void CLiveSession::writeLiveJson(const TLiveJsonState& st)
{
	writeTextFileAtomically((std::filesystem::path(m_setup.outDir) / "live.json").string(),
							liveJson(st));
}

void CLiveSession::writeLiveJson(const std::string& status)
{
	TLiveJsonState st = liveState(status);
	st.saves = m_saves;
	writeLiveJson(st);
}

void CLiveSession::summary(const std::string& status)
{
	if (m_fatal.isSet())
		m_console.message("lrgc-slam: " + status + " (what was mapped is saved)", true);
	else if (status != "stopped on request")
		m_console.message("lrgc-slam: " + status, true);
	m_console.message(
		mrpt::format("lrgc-slam: live run %s: %llu scans received (%llu objects captured), "
					 "%s; outputs in %s",
					 m_fatal.isSet() ? "failed" : "stopped",
					 static_cast<unsigned long long>(m_queues.scansPushed()),
					 static_cast<unsigned long long>(m_capture.objects()),
					 m_processor->summaryText().c_str(), m_setup.outDir.c_str()),
		m_fatal.isSet());
}

}  // namespace lrgc::apps
