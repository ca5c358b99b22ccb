#include "lrgc_apps/SlamApp.h"

#include "lrgc_apps/AppConfig.h"
#include "lrgc_apps/RunOutputs.h"
#include "lrgc_apps/atomic_file.h"

#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>

#include <atomic>
#include <csignal>
#include <signal.h>
#include <unistd.h>

namespace lrgc::apps
{
namespace
{
// The one piece of global state: a signal handler can only reach a global flag.
std::atomic<int> g_stopSignals{0};

extern "C" void onStopSignal(int)
{
	if (g_stopSignals.fetch_add(1) >= 1) ::_exit(kExitInterrupted);  // second signal: now
}

}  // namespace

void installStopSignalHandlers()
{
	// sigaction, not std::signal: with -std=c++17 (strict ANSI) glibc's signal() has System V
	// semantics and resets the handler after the first signal, so a second SIGTERM would kill
	// the process with the default action (status 143) instead of reaching _exit(130) here.
	struct sigaction sa = {};
	sa.sa_handler = onStopSignal;
	sigemptyset(&sa.sa_mask);
	sa.sa_flags = SA_RESTART;
	::sigaction(SIGINT, &sa, nullptr);
	::sigaction(SIGTERM, &sa, nullptr);
}
bool stopRequested() { return g_stopSignals.load() > 0; }
void clearStopRequest() { g_stopSignals = 0; }

void CSlamApp::report(const std::string& line)
{
	std::fprintf(m_err, "%s\n", line.c_str());
	std::fflush(m_err);
}

int CSlamApp::run(const std::vector<std::string>& args)
{
	TSlamCommandLine cl;
	try
	{
		cl = parseSlamCommandLine(args);
		if (cl.help) { std::fputs(slamUsage().c_str(), stdout); return kExitOk; }
		if (cl.version) { std::printf("lrgc-slam %s\n", LRGC_VERSION); return kExitOk; }
		if (!cl.writeDefaultConfig.empty())
		{
			writeTextFileAtomically(cl.writeDefaultConfig, defaultAppConfigText());
			return kExitOk;
		}
		if (!cl.outDir.empty()) checkOutputDirectory(cl.outDir);
		if (!cl.live.empty())
		{
			if (!m_live)
				throw CUsageError(
					"--live: this program was built without live sensor support (link "
					"lrgc_live and pass lrgc::apps::runLiveSlam to CSlamApp)");
			return m_live(cl, m_err);
		}
		if (!cl.saveRawlog.empty())
			if (const int rc = convertOnly(cl); rc != kExitOk || cl.outDir.empty()) return rc;
		return runOffline(cl);
	}
	catch (const CSetupError& e)
	{
		report(std::string("lrgc-slam: ") + e.what());
		return kExitUsage;
	}
	catch (const CUsageError& e)
	{
		report(std::string("lrgc-slam: ") + e.what());
		report(slamUsage());
		return kExitUsage;
	}
	catch (const std::exception& e)
	{
		report("lrgc-slam: error: " + mrpt::exception_to_str(e));
		return kExitInputError;
	}
}

int CSlamApp::convertOnly(const TSlamCommandLine& cl)
{
	const TAppConfig cfg = loadAppConfig(cl.config);
	try
	{
		const TConversionStats st = convertToRawlog(cl.input, cl.saveRawlog, cfg.reader);
		if (!cl.quiet)
			report(mrpt::format(
				"converted '%s' -> '%s': %zu scans, %zu odometry readings, %zu warnings",
				cl.input.c_str(), cl.saveRawlog.c_str(), st.scans, st.odometry, st.warnings));
		return kExitOk;
	}
	catch (const std::exception& e)
	{
		report("lrgc-slam: cannot convert: " + mrpt::exception_to_str(e));
		return kExitInputError;
	}
}

}  // namespace lrgc::apps
