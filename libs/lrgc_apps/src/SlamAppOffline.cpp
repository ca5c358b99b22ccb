/* CSlamApp::runOffline: the log-to-maps loop of lrgc-slam. */
#include "lrgc_apps/AppConfig.h"
#include "lrgc_apps/Progress.h"
#include "lrgc_apps/RunOutputs.h"
#include "lrgc_apps/RunStats.h"
#include "lrgc_apps/SlamApp.h"
#include "lrgc_apps/io/LogReader.h"

#include <lrgc/map_builder/CMetricMapBuilderLRGC.h>
#include <mrpt/obs/CActionCollection.h>

#include <algorithm>
#include <chrono>

namespace lrgc::apps
{
namespace
{
constexpr size_t kMaxWarningsShown = 30;

void feed(CMetricMapBuilderLRGC& builder, TLogEntry& e)
{
	if (e.observations)
	{
		mrpt::obs::CActionCollection noActions;
		builder.processActionObservation(e.actions ? *e.actions : noActions, *e.observations);
	}
	else if (e.observation)
		builder.processObservation(e.observation);
}
}  // namespace

int CSlamApp::runOffline(const TSlamCommandLine& cl)
{
	const TAppConfig cfg = loadAppConfig(cl.config);
	std::unique_ptr<CLogReader> reader;
	try
	{
		reader = openLog(cl.input, cfg.reader);
	}
	catch (const std::exception& e)
	{
		report("lrgc-slam: " + mrpt::exception_to_str(e));
		return kExitInputError;
	}

	installStopSignalHandlers();
	CMetricMapBuilderLRGC builder(cfg.lrgc);
	builder.logging_enable_console_output = false;  // warnings are reported below
	CProgress progress(m_err, cl.quiet);
	CRunClock clock;
	TRunSummary run;
	run.input = cl.input;
	run.format = detectLogFormat(cl.input) == LogFormat::Carmen ? "carmen" : "rawlog";
	int exitCode = kExitOk;

	auto flushWarnings = [&](std::vector<std::string> ws) {
		for (auto& w : ws)
		{
			++m_warningsTotal;
			if (m_warningsShown++ < kMaxWarningsShown) report("warning: " + w);
			else if (m_warningsShown == kMaxWarningsShown + 1)
				report("warning: further warnings are counted in stats.json, not shown");
		}
	};

	while (!stopRequested())
	{
		std::optional<TLogEntry> entry;
		try
		{
			entry = reader->next();
		}
		catch (const std::exception& e)
		{
			run.status = "input error: " + mrpt::exception_to_str(e);
			exitCode = kExitInputError;
			break;
		}
		if (!entry) break;
		++run.logEntries;
		const size_t scansBefore = builder.stats().scans;
		const auto t0 = std::chrono::steady_clock::now();
		try
		{
			feed(builder, *entry);
		}
		catch (const std::exception& e)
		{
			run.status = "error at " + entry->where + ": " + mrpt::exception_to_str(e);
			exitCode = kExitInputError;
			break;
		}
		if (builder.stats().scans > scansBefore)
		{
			run.latencyMs.push_back(
				std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
					.count());
			run.latencyStamp.push_back(mrpt::Clock::toDouble(builder.lastScanTimestamp()));
		}
		flushWarnings(reader->takeWarnings());
		flushWarnings(builder.takeWarnings());
		progress.update(
			reader->fractionRead(), builder.stats().scans,
			mrpt::format("kf %zu  loops %zu", builder.stats().keyframes, builder.stats().loopClosures));
	}
	if (stopRequested() && exitCode == kExitOk)
	{
		run.status = "interrupted";
		exitCode = kExitInterrupted;
	}

	const auto tFinal = std::chrono::steady_clock::now();
	builder.finish();
	run.finalOptimizationSeconds =
		std::chrono::duration<double>(std::chrono::steady_clock::now() - tFinal).count();
	progress.finish(builder.stats().scans);

	if (!run.latencyStamp.empty())
	{
		const auto [lo, hi] = std::minmax_element(run.latencyStamp.begin(), run.latencyStamp.end());
		run.dataDurationSeconds = *hi - *lo;
	}
	run.warnings = m_warningsTotal;
	run.wallSeconds = clock.wallSeconds();
	run.cpuSeconds = clock.cpuSeconds();
	run.peakRssMiB = CRunClock::peakRssMiB();
	writeRunOutputs(builder, cl.outDir, run);

	const auto& s = builder.stats();
	if (exitCode != kExitOk) report("lrgc-slam: " + run.status + " (maps of what was read are saved)");
	if (!cl.quiet || exitCode != kExitOk)
		report(mrpt::format(
			"lrgc-slam: %zu scans, %zu keyframes, %zu loop closures, %.1f s of data in %.1f s "
			"(%.0fx real time); outputs in %s",
			s.scans, s.keyframes, s.loopClosures, run.dataDurationSeconds, run.wallSeconds,
			run.wallSeconds > 0 ? run.dataDurationSeconds / run.wallSeconds : 0.0,
			cl.outDir.c_str()));
	return exitCode;
}

}  // namespace lrgc::apps
