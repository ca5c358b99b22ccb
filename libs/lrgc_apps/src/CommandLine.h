/* Command line of lrgc-slam.
 *
 *   lrgc-slam --input FILE [--config FILE.ini] --out DIR [--laser LABEL] [--quiet]
 *             [--save-rawlog OUT.rawlog] [--progress-interval SECONDS]
 *   lrgc-slam --input FILE --save-rawlog OUT.rawlog          (convert only)
 *   lrgc-slam --live SENSORS.ini [--config FILE.ini] --out DIR [--quiet]   (live sensors)
 *   lrgc-slam --input FILE --initial-map MAP --out DIR     (continue MAP: DIR or .simplemap)
 *   lrgc-slam --input FILE --localize MAP --out DIR        (localise on MAP, no mapping)
 *   lrgc-slam --merge MAP_A MAP_B --out DIR              (B's keyframes joined into A's map)
 *   lrgc-slam --write-default-config FILE.ini [--expert] [--force]
 *   lrgc-slam ICP-SLAM.ini [RAWLOG] [--config FILE.ini]      (icp-slam's command line:
 * IcpSlamIni.h)
 *   --input and --live runs [--laser LABEL]: the laser to map (others are counted, ignored)
 *   any of them [--verbose]: on an error, MRPT's details (source location, call stack) too
 */
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace lrgc::apps
{
struct TSlamCommandLine
{
	std::string input;   //!< log file (rawlog or CARMEN)
	std::string live;    //!< rawlog-grabber .ini of the live sensors (instead of --input)
	std::string config;  //!< optional .ini with lrgc parameters
	std::string outDir;
	std::string saveRawlog;          //!< convert the input into this MRPT rawlog
	std::string writeDefaultConfig;  //!< write the default .ini and exit
	// --- continuing and localising on a saved map (issue 14) ---
	/** An earlier output folder or a .simplemap(.gz): the run continues that map. */
	std::string initialMap;
	/** An earlier output folder or a .simplemap(.gz): localise on it, never change it. */
	std::string localize;
	/** --merge MAP_A MAP_B (issue 29): two saved maps (output folders or .simplemap(.gz)),
	 * merged into one map in MAP_A's frame. Both empty unless --merge is given. */
	std::string mergeA, mergeB;
	bool force = false;   //!< --write-default-config may replace an existing file
	bool expert = false;  //!< --write-default-config writes every key, not the user's few
	bool quiet = false;
	/** [s] --progress-interval: seconds between progress lines when stderr is not a
	 * terminal (logs, pipes, CI); a terminal's bar is redrawn every 0.2 s whatever this is. */
	double progressInterval = 10.0;
	bool verbose = false;  //!< errors with their details (source location, call stack)
	bool help = false;
	bool version = false;

	// --- which laser to map (issue 14) ---
	std::string laser;  //!< --laser LABEL: overrides [MapBuilder] laser_label

	// --- icp-slam's command line (IcpSlamIni.h) ---
	std::string icpSlamIni;     //!< first positional argument: an icp-slam .ini
	std::string icpSlamRawlog;  //!< second positional argument: overrides its rawlog_file
};

/** A usage error: the message says what is wrong; the caller prints usage and exits 2. */
class CUsageError : public std::runtime_error
{
public:
	using std::runtime_error::runtime_error;
};

/** A bad configuration file or output file or directory: exit 2 like a usage error, but the
 * message alone says what to do. `details`: what --verbose adds (the call stack of the
 * exception behind it), if any. */
class CSetupError : public CUsageError
{
public:
	explicit CSetupError(const std::string& what, std::string details = {})
		: CUsageError(what), m_details(std::move(details))
	{
	}
	const std::string& details() const { return m_details; }

private:
	std::string m_details;
};

/** Parses argv (argv[0] excluded); throws CUsageError naming the offending argument. */
TSlamCommandLine parseSlamCommandLine(const std::vector<std::string>& args);

std::string slamUsage();

}  // namespace lrgc::apps
