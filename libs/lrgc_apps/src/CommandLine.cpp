#include "CommandLine.h"

#include <cmath>
#include <exception>
#include <filesystem>
#include <string>
#include <system_error>

namespace lrgc::apps
{
namespace
{
constexpr const char* kSeeHelp = "; lrgc-slam --help lists the options";

// --- continuing and localising on a saved map (issue 14) ---
bool parseSavedMapOption(const std::vector<std::string>& args, size_t& i, TSlamCommandLine& cl)
{
	const std::string& a = args[i];
	std::string* dst = a == "--initial-map" ? &cl.initialMap
					   : a == "--localize"  ? &cl.localize
											: nullptr;
	if (!dst) return false;
	if (i + 1 >= args.size() || args[i + 1].rfind("--", 0) == 0)
		throw CUsageError("option " + a +
						  " needs a value (an lrgc output folder or a "
						  ".simplemap file)" +
						  kSeeHelp);
	*dst = args[++i];
	return true;
}

// --progress-interval SECONDS: a positive, finite number of seconds.
double progressInterval(const std::string& value)
{
	size_t used = 0;
	double s = 0;
	try
	{
		s = std::stod(value, &used);
	}
	catch (const std::exception&)
	{
		used = 0;
	}
	if (used != value.size() || !std::isfinite(s) || s <= 0)
		throw CUsageError("--progress-interval needs a number of seconds above 0, not '" +
						  value + "'");
	return s;
}

// --merge MAP_A MAP_B: two values, each a folder or a file, never an option.
bool parseMergeOption(const std::vector<std::string>& args, size_t& i, TSlamCommandLine& cl)
{
	if (args[i] != "--merge") return false;
	for (std::string* dst : {&cl.mergeA, &cl.mergeB})
	{
		if (i + 1 >= args.size() || args[i + 1].rfind("--", 0) == 0)
			throw CUsageError(
				"option --merge needs two values, MAP_A MAP_B (each an lrgc output folder or "
				"a .simplemap file)" +
				std::string(kSeeHelp));
		*dst = args[++i];
	}
	return true;
}

// --merge replays MAP_B into MAP_A: no log, no sensor, no other saved map.
void checkMergeOptions(const TSlamCommandLine& cl)
{
	for (const auto& [given, option] : {std::pair{!cl.input.empty(), "--input"},
										{!cl.live.empty(), "--live"},
										{!cl.initialMap.empty(), "--initial-map"},
										{!cl.localize.empty(), "--localize"},
										{!cl.saveRawlog.empty(), "--save-rawlog"}})
		if (given)
			throw CUsageError(std::string("--merge takes no ") + option +
							  " (it merges two saved maps: lrgc-slam --merge MAP_A MAP_B --out "
							  "DIR)");
	if (cl.outDir.empty()) throw CUsageError("--merge needs --out DIR" + std::string(kSeeHelp));
}

void checkSavedMapOptions(const TSlamCommandLine& cl)
{
	if (cl.initialMap.empty() && cl.localize.empty()) return;
	if (!cl.initialMap.empty() && !cl.localize.empty())
		throw CUsageError(
			"--initial-map and --localize exclude each other (continue a map, or localise on "
			"it without changing it)");
	const std::string opt = cl.initialMap.empty() ? "--localize" : "--initial-map";
	if (cl.input.empty() && cl.live.empty())
		throw CUsageError(opt + " needs --input FILE or --live SENSORS.ini" + kSeeHelp);
	if (cl.outDir.empty()) throw CUsageError(opt + " needs --out DIR" + kSeeHelp);
}
// lrgc-slam ICP-SLAM.ini [RAWLOG]: the .ini names the input and the output folder.
const TSlamCommandLine& checkIcpSlamCommandLine(const TSlamCommandLine& cl)
{
	for (const auto& [given, option] : {std::pair{!cl.input.empty(), "--input"},
										{!cl.live.empty(), "--live"},
										{!cl.outDir.empty(), "--out"},
										{!cl.initialMap.empty(), "--initial-map"},
										{!cl.localize.empty(), "--localize"},
										{!cl.mergeA.empty(), "--merge"},
										{!cl.saveRawlog.empty(), "--save-rawlog"}})
		if (given)
			throw CUsageError("'" + cl.icpSlamIni +
							  "' runs as icp-slam's CONFIG.ini [RAWLOG] "
							  "(its [MappingApplication] names the input and the output "
							  "folder), which takes no " +
							  std::string(option) + kSeeHelp);
	return cl;
}
}  // namespace

namespace
{
// The options of a run must go together: each refusal names the option and what to do.
TSlamCommandLine checkedRunOptions(TSlamCommandLine& cl)
{
	if (cl.force && cl.writeDefaultConfig.empty())
		throw CUsageError(
			"--force is for --write-default-config (a run replaces only its own outputs in "
			"--out, and never the input)");
	if (cl.expert && cl.writeDefaultConfig.empty())
		throw CUsageError("--expert is for --write-default-config (it writes every key)");
	if (!cl.writeDefaultConfig.empty()) return cl;
	if (!cl.icpSlamIni.empty()) return checkIcpSlamCommandLine(cl);
	if (!cl.mergeA.empty())
	{
		checkMergeOptions(cl);
		return cl;
	}
	checkSavedMapOptions(cl);
	if (!cl.live.empty())
	{
		if (!cl.input.empty()) throw CUsageError("--live and --input exclude each other");
		if (!cl.saveRawlog.empty())
			throw CUsageError(
				"--save-rawlog is for --input; a live run writes DIR/capture.rawlog");
		if (cl.outDir.empty())
			throw CUsageError("missing --out DIR for --live" + std::string(kSeeHelp));
		return cl;
	}
	if (cl.input.empty())
		throw CUsageError("missing --input FILE (or --live SENSORS.ini)" +
						  std::string(kSeeHelp));
	if (cl.outDir.empty() && cl.saveRawlog.empty())
		throw CUsageError("missing --out DIR (or --save-rawlog FILE to convert only)" +
						  std::string(kSeeHelp));
	if (!cl.laser.empty() && cl.outDir.empty())
		throw CUsageError(
			"--laser picks the laser to map (with --out DIR); --save-rawlog "
			"alone converts every laser");
	// Never write over the input (a CARMEN log would be gone, a layout-1 rawlog would become
	// observations-only): the same file under any spelling of its path, links included.
	std::error_code ec;
	if (!cl.saveRawlog.empty() && std::filesystem::equivalent(cl.input, cl.saveRawlog, ec))
		throw CUsageError("--save-rawlog '" + cl.saveRawlog + "' is the input file '" +
						  cl.input + "': refusing to overwrite it; name another file");
	return cl;
}
}  // namespace

TSlamCommandLine parseSlamCommandLine(const std::vector<std::string>& args)
{
	TSlamCommandLine cl;
	for (size_t i = 0; i < args.size(); ++i)
	{
		const std::string& a = args[i];
		auto value = [&](std::string& dst)
		{
			if (i + 1 >= args.size() || args[i + 1].rfind("--", 0) == 0)
				throw CUsageError("option " + a + " needs a value" + kSeeHelp);
			dst = args[++i];
		};
		// --- which laser to map (issue 14): its own block ---
		if (a == "--laser")
		{
			value(cl.laser);
			continue;
		}
		if (a == "--input" || a == "-i")
			value(cl.input);
		else if (a == "--live")
			value(cl.live);
		else if (a == "--config" || a == "-c")
			value(cl.config);
		else if (a == "--out" || a == "-o")
			value(cl.outDir);
		else if (a == "--save-rawlog")
			value(cl.saveRawlog);
		else if (a == "--write-default-config")
			value(cl.writeDefaultConfig);
		else if (parseSavedMapOption(args, i, cl) || parseMergeOption(args, i, cl))
			continue;
		else if (a == "--force")
			cl.force = true;
		else if (a == "--expert")
			cl.expert = true;
		else if (a == "--quiet" || a == "-q")
			cl.quiet = true;
		else if (a == "--progress-interval")
		{
			std::string seconds;
			value(seconds);
			cl.progressInterval = progressInterval(seconds);
		}
		else if (a == "--verbose" || a == "-v")
			cl.verbose = true;
		else if (a == "--help" || a == "-h")
			cl.help = true;
		else if (a == "--version")
			cl.version = true;
		else if (!a.empty() && a[0] != '-' && cl.icpSlamRawlog.empty())
			(cl.icpSlamIni.empty() ? cl.icpSlamIni : cl.icpSlamRawlog) = a;  // icp-slam's
		else
			throw CUsageError("unknown argument '" + a + "'" + kSeeHelp);
	}
	if (cl.help || cl.version) return cl;
	return checkedRunOptions(cl);
}

std::string slamUsage()
{
	return "Usage:\n"
		   "  lrgc-slam --input FILE [--config FILE.ini] --out DIR [--laser LABEL] [--quiet]\n"
		   "            [--save-rawlog R]\n"
		   "  lrgc-slam --input FILE --save-rawlog OUT.rawlog     convert to an MRPT rawlog\n"
		   "  lrgc-slam --live SENSORS.ini [--config FILE.ini] --out DIR [--laser LABEL] "
		   "[--quiet]\n"
		   "  lrgc-slam --input FILE --initial-map MAP --out DIR   continue a saved map\n"
		   "  lrgc-slam --input FILE --localize MAP --out DIR      localise on a saved map\n"
		   "  lrgc-slam --live SENSORS.ini --initial-map MAP | --localize MAP --out DIR\n"
		   "  lrgc-slam --merge MAP_A MAP_B --out DIR            merge two overlapping maps\n"
		   "  lrgc-slam --write-default-config FILE.ini [--expert] [--force]\n"
		   "  lrgc-slam ICP-SLAM.ini [RAWLOG] [--config FILE.ini]  icp-slam's command line\n"
		   "  lrgc-slam --help | --version\n"
		   "Options: -i --input, -c --config, -o --out, -q --quiet (no progress), -v "
		   "--verbose\n"
		   "(on an error, also its details: source location, call stack), --force (replace an\n"
		   "existing FILE.ini), -h --help, --version (print the version and exit),\n"
		   "--progress-interval SECONDS (between progress lines when stderr is no terminal;\n"
		   "default 10).\n"
		   "FILE: MRPT rawlog (.rawlog, plain or gzip, both layouts) or CARMEN log\n"
		   "(.clf/.log, optionally .gz); the format is detected from the content.\n"
		   "Outputs in DIR: map.gridmap.gz map.png map.pgm map.yaml map.simplemap.gz "
		   "map.3Dscene\n"
		   "trajectory.tum graph.graph graph.lrgc timing.csv stats.json pf-localization.ini\n"
		   "observations2map.ini (for MRPT's programs) config.ini (the\n"
		   "configuration used: --config DIR/config.ini repeats the run). An existing DIR is\n"
		   "kept: only these files are written (over those of an earlier run); no other file\n"
		   "is changed or deleted.\n"
		   "--live: map from the sensors of a rawlog-grabber .ini (mrpt::hwdrivers drivers)\n"
		   "until Ctrl-C or SIGTERM; everything received goes to DIR/capture.rawlog, maps are\n"
		   "saved every [LiveMapping] save_interval_s and at the end, live.json has "
		   "per-sensor\n"
		   "counts. A second Ctrl-C exits at once (the capture and last saved maps stay "
		   "valid).\n"
		   "--laser LABEL: map the 2D laser of this sensorLabel (a CARMEN log's FLASER is\n"
		   "LASER, RLASER is REAR_LASER) and ignore the others; default [MapBuilder]\n"
		   "laser_label, empty: the first laser seen (a second one is warned about).\n"
		   "MAP: an earlier output DIR (its graph.lrgc and map.simplemap.gz: the whole graph)\n"
		   "or any MRPT .simplemap(.gz), e.g. icp-slam's. --initial-map: FILE (or the live\n"
		   "scans) is mapped from its first scan as a piece of its own, joined to MAP where\n"
		   "global correlation places it (never joined: kept in its own frame, exit 0); DIR\n"
		   "gets the whole map (old + new), its trajectory.tum FILE's scans. --localize: the\n"
		   "start in MAP is found by global correlation; MAP is not changed; DIR gets\n"
		   "trajectory.tum, timing.csv and stats.json (relocalisations, latency).\n"
		   "--merge MAP_A MAP_B: MAP_B's keyframes (their scans, their poses as odometry) are\n"
		   "replayed as a piece beside MAP_A and joined to it where global correlation places\n"
		   "them; DIR gets one map in MAP_A's frame (MAP_A's keyframes as saved), its\n"
		   "trajectory.tum MAP_B's poses in that frame, stats.json's \"merge\" the transform\n"
		   "(A <- B). Maps that do not overlap: exit 1, nothing written.\n"
		   "ICP-SLAM.ini: an icp-slam .ini; its [MappingApplication] rawlog_file (or RAWLOG),\n"
		   "rawlog_offset (rawlog objects to skip) and logOutput_dir are used, its others\n"
		   "are reported as ignored (lrgc's parameters map). logOutput_dir gets lrgc's "
		   "outputs\n"
		   "and icp-slam's _finalmap_.simplemap and log_estimated_path.txt (step x y phi).\n";
}

}  // namespace lrgc::apps
