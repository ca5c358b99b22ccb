/* CSlamApp: lrgc-slam as a library class, so tests drive the whole application.
 *
 * Offline: streams a log (rawlog or CARMEN) into CMetricMapBuilderLRGC, reports progress,
 * and writes every output atomically into the output directory. A problem the run can go on
 * from (a malformed line, a skipped scan) is reported and skipped; one it cannot (a
 * truncated or corrupt rawlog) ends the run with the maps built so far saved and a non-zero
 * exit status. SIGINT/SIGTERM stop the run the same way.
 */
#pragma once

#include <lrgc_apps/CommandLine.h>

#include <cstdio>
#include <string>
#include <vector>

namespace lrgc::apps
{
/** Exit statuses of lrgc-slam. */
enum ExitStatus : int
{
	kExitOk = 0,
	kExitInputError = 1,  //!< the input could not be read to the end: maps so far saved
	kExitUsage = 2,  //!< bad command line or configuration: nothing was run
	kExitInterrupted = 130  //!< SIGINT/SIGTERM: maps so far saved
};

class CSlamApp
{
   public:
	/** err: where progress, warnings and errors go (stderr in the real app). */
	explicit CSlamApp(std::FILE* err = stderr) : m_err(err) {}

	/** Runs lrgc-slam with argv without argv[0]; returns the exit status. Never throws. */
	int run(const std::vector<std::string>& args);

   private:
	int runOffline(const TSlamCommandLine& cl);
	int convertOnly(const TSlamCommandLine& cl);
	void report(const std::string& line);

	std::FILE* m_err;
	size_t m_warningsShown = 0, m_warningsTotal = 0;
};

/** Installs SIGINT/SIGTERM handlers that ask running CSlamApp loops to stop (a second
 * signal exits at once); returns whether a stop was requested. */
void installStopSignalHandlers();
bool stopRequested();
void clearStopRequest();

}  // namespace lrgc::apps
