#include "IcpSlamIni.h"

#include "AppConfig.h"
#include "CommandLine.h"
#include "ErrorText.h"
#include "atomic_file.h"

#include <mrpt/config/CConfigFile.h>
#include <mrpt/core/format.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace lrgc::apps
{
namespace
{
const char* const kSection = "MappingApplication";

std::string where(const std::string& path, const std::string& key)
{
	const auto line = iniLineOf(path, kSection, key);
	return line ? path + ":" + std::to_string(*line) : path;
}

std::string readText(const std::string& path)
{
	std::ifstream in(path, std::ios::binary);
	std::ostringstream s;
	s << in.rdbuf();
	return s.str();
}

std::string requiredPath(const mrpt::config::CConfigFile& ini, const std::string& path,
						 const std::string& key)
{
	const std::string v = ini.read_string(kSection, key, "");
	if (v.empty())
		throw CSetupError(where(path, key) + ": [MappingApplication] " + key +
						  " is missing or empty; icp-slam's .ini names the " +
						  (key == "rawlog_file" ? "input rawlog" : "output folder") + " there");
	return v;
}
}  // namespace

bool isIcpSlamIni(const std::string& path)
{
	std::error_code ec;
	if (!std::filesystem::is_regular_file(path, ec)) return false;
	// Streamed, and only the start of it: a rawlog given by mistake may be gigabytes.
	std::ifstream text(path, std::ios::binary);
	size_t lines = 0;
	for (std::string line; lines++ < 100000 && std::getline(text, line);)
	{
		const size_t a = line.find_first_not_of(" \t");
		if (a == std::string::npos || line[a] != '[') continue;
		const size_t b = line.find(']', a);
		if (b != std::string::npos && sameIniName(line.substr(a + 1, b - a - 1), kSection))
			return true;
	}
	return false;
}

TIcpSlamRun readIcpSlamIni(const std::string& path, const std::string& rawlogOverride)
{
	TIcpSlamRun run;
	std::unique_ptr<mrpt::config::CConfigFile> ini;
	try
	{
		ini = std::make_unique<mrpt::config::CConfigFile>(path);
	}
	catch (const std::exception& e)
	{
		throw CSetupError(path + ": " + oneLineError(e), errorDetails(e));
	}
	run.rawlog =
		rawlogOverride.empty() ? requiredPath(*ini, path, "rawlog_file") : rawlogOverride;
	run.outDir = requiredPath(*ini, path, "logOutput_dir");
	const std::string offset = ini->read_string(kSection, "rawlog_offset", "0");
	if (offset.empty() || offset.find_first_not_of("0123456789") != std::string::npos)
		throw CSetupError(where(path, "rawlog_offset") +
						  ": [MappingApplication] rawlog_offset '" + offset +
						  "' is not a whole number >= 0 (rawlog objects to skip)");
	run.rawlogOffset = std::stoul(offset);

	std::vector<std::string> sections;
	ini->getAllSections(sections);
	for (const auto& section : sections)
	{
		if (!sameIniName(section, kSection))
		{
			run.ignored.push_back("[" + section + "]");
			continue;
		}
		std::vector<std::string> keys;
		ini->getAllKeys(section, keys);
		for (const auto& key : keys)
			if (!sameIniName(key, "rawlog_file") && !sameIniName(key, "rawlog_offset") &&
				!sameIniName(key, "logOutput_dir"))
				run.ignored.push_back(key);
	}
	return run;
}

std::string ignoredIcpSlamSettings(const std::string& path, const TIcpSlamRun& run)
{
	if (run.ignored.empty()) return {};
	std::string sections, keys;
	for (const auto& name : run.ignored)
	{
		std::string& list = name.front() == '[' ? sections : keys;
		list += (list.empty() ? "" : " ") + name;
	}
	std::string line = "'" + path +
					   "': icp-slam settings lrgc does not use, ignored (it maps with "
					   "its own parameters: --config FILE.ini):";
	if (!sections.empty()) line += " sections " + sections;
	if (!keys.empty())
		line += std::string(sections.empty() ? "" : ";") + " [MappingApplication] " + keys;
	return line;
}

std::string icpSlamEstimatedPath(const TTrajectory& trajectory,
								 const std::vector<size_t>& scansAfterEntry)
{
	std::string out;
	for (size_t step = 0; step < scansAfterEntry.size(); ++step)
	{
		const size_t scans = std::min(scansAfterEntry[step], trajectory.size());
		if (scans == 0) continue;
		const auto& p = trajectory[scans - 1].robotInMap;
		out += mrpt::format("%zu %f %f %f\n", step, p.x, p.y, p.phi);
	}
	return out;
}

void writeIcpSlamOutputs(const std::string& outDir, const TTrajectory& trajectory,
						 const std::vector<size_t>& scansAfterEntry)
{
	namespace fs = std::filesystem;
	const fs::path dir(outDir);
	if (fs::exists(dir / "map.simplemap.gz"))
		writeTextFileAtomically((dir / "_finalmap_.simplemap").string(),
								readText((dir / "map.simplemap.gz").string()));
	writeTextFileAtomically((dir / "log_estimated_path.txt").string(),
							icpSlamEstimatedPath(trajectory, scansAfterEntry));
}

}  // namespace lrgc::apps
