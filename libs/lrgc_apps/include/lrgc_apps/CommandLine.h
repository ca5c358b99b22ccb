/* Command line of lrgc-slam.
 *
 *   lrgc-slam --input FILE [--config FILE.ini] --out DIR [--quiet] [--save-rawlog OUT.rawlog]
 *   lrgc-slam --input FILE --save-rawlog OUT.rawlog          (convert only)
 *   lrgc-slam --live SENSORS.ini [--config FILE.ini] --out DIR [--quiet]   (live sensors)
 *   lrgc-slam --write-default-config FILE.ini
 */
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace lrgc::apps
{
struct TSlamCommandLine
{
	std::string input;  //!< log file (rawlog or CARMEN)
	std::string live;  //!< rawlog-grabber .ini of the live sensors (instead of --input)
	std::string config;  //!< optional .ini with lrgc parameters
	std::string outDir;
	std::string saveRawlog;  //!< convert the input into this MRPT rawlog
	std::string writeDefaultConfig;  //!< write the default .ini and exit
	bool quiet = false;
	bool help = false;
	bool version = false;
};

/** A usage error: the message says what is wrong; the caller prints usage and exits 2. */
class CUsageError : public std::runtime_error
{
   public:
	using std::runtime_error::runtime_error;
};

/** A bad configuration file or output directory: exit 2 like a usage error, but the message
 * alone says what to do, so the usage text is not printed after it. */
class CSetupError : public CUsageError
{
public:
	using CUsageError::CUsageError;
};

/** Parses argv (argv[0] excluded); throws CUsageError naming the offending argument. */
TSlamCommandLine parseSlamCommandLine(const std::vector<std::string>& args);

std::string slamUsage();

}  // namespace lrgc::apps
