#include "AppConfig.h"

#include "CommandLine.h"
#include "ErrorText.h"

#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <lrgc/common/params_io.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace lrgc::apps
{
namespace
{
std::string trimmed(const std::string& s)
{
	const size_t a = s.find_first_not_of(" \t\r");
	if (a == std::string::npos) return {};
	return s.substr(a, s.find_last_not_of(" \t\r") - a + 1);
}

// A UTF-8 byte order mark (some editors write one) is no part of the first line; MRPT's
// parser skips it too.
std::string withoutByteOrderMark(const std::string& line)
{
	return line.rfind("\xEF\xBB\xBF", 0) == 0 ? line.substr(3) : line;
}

// MRPT's CConfigFile files a key written before the first [section] under section "", where
// no loader looks: throws naming the first such line.
void rejectKeysBeforeTheFirstSection(const std::string& path)
{
	std::ifstream in(path);
	size_t n = 0;
	for (std::string raw; std::getline(in, raw);)
	{
		const std::string line = trimmed(++n == 1 ? withoutByteOrderMark(raw) : raw);
		if (line.empty() || line[0] == '#' || line[0] == ';' || line.rfind("//", 0) == 0)
			continue;
		if (line[0] == '[') return;
		throw CSetupError(
			path + ":" + std::to_string(n) + ": '" + line.substr(0, 60) +
			"' comes before the first [section], so no section reads it; move it "
			"under its section (lrgc-slam --write-default-config FILE writes every "
			"section and key)");
	}
}

// MRPT's config_parser() reports "Line N: what" (1-based): {N, what}.
std::optional<std::pair<size_t, std::string>> parserLineOf(const std::string& message)
{
	const std::string prefix = "Line ";
	if (message.rfind(prefix, 0) != 0) return std::nullopt;
	size_t end = prefix.size();
	while (end < message.size() && std::isdigit(static_cast<unsigned char>(message[end])))
		++end;
	if (end == prefix.size() || end + 1 >= message.size() || message[end] != ':')
		return std::nullopt;
	size_t line = 0;
	const char* digits = message.data() + prefix.size();
	if (std::from_chars(digits, message.data() + end, line).ec != std::errc())
		return std::nullopt;
	return std::make_pair(line, trimmed(message.substr(end + 1)));
}
}  // namespace

bool sameIniName(const std::string& a, const std::string& b)
{
	return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(),
											  [](unsigned char x, unsigned char y)
											  { return std::tolower(x) == std::tolower(y); });
}

std::optional<size_t> iniLineOf(const std::string& path, const std::string& section,
								const std::string& key)
{
	std::ifstream in(path);
	std::string current;
	size_t n = 0;
	std::optional<size_t> last;  // MRPT reads the last of repeated keys
	for (std::string raw; std::getline(in, raw);)
	{
		++n;
		const std::string line = trimmed(n == 1 ? withoutByteOrderMark(raw) : raw);
		if (line.empty() || line[0] == '#' || line[0] == ';' || line.rfind("//", 0) == 0)
			continue;
		if (line[0] == '[')
		{
			const size_t close = line.find(']');
			current = trimmed(line.substr(1, close == std::string::npos ? close : close - 1));
			if (key.empty() && sameIniName(current, section)) return n;
			continue;
		}
		const size_t eq = line.find('=');
		if (!key.empty() && eq != std::string::npos && sameIniName(current, section) &&
			sameIniName(trimmed(line.substr(0, eq)), key))
			last = n;
	}
	return last;
}

const std::vector<lrgc::TRenamedKey>& appRenamedKeys()
{
	static const std::vector<lrgc::TRenamedKey> renamed = {
		{"Localization", "patch_max_range", "patch_max_range_m", ""},
		{"Localization", "track_radius", "track_radius_m", ""},
		{"Localization", "min_inliers", "min_inlier_fraction", ""}};
	return renamed;
}

namespace
{
// iniLineOf(), also where the file writes the key under an old name (appRenamedKeys(),
// TLRGCParams::renamedKeys()).
std::optional<size_t> lineOfKey(const std::string& path, const std::string& section,
								const std::string& key)
{
	if (const auto line = iniLineOf(path, section, key)) return line;
	for (const auto* table : {&TLRGCParams::renamedKeys(), &appRenamedKeys()})
		for (const auto& r : *table)
			if (!key.empty() && r.section == section && r.newKey == key)
				if (const auto line = iniLineOf(path, section, r.oldKey)) return line;
	return std::nullopt;
}
}  // namespace

TAppConfig loadAppConfig(const std::string& path)
{
	TAppConfig cfg;
	if (path.empty()) return cfg;
	if (std::filesystem::is_directory(path))
		throw CSetupError("--config '" + path +
						  "' is a folder; name an .ini file in it (lrgc-slam "
						  "--write-default-config FILE writes one)");
	if (!std::filesystem::is_regular_file(path))
		throw CSetupError("--config '" + path +
						  "': no such file; name an existing .ini (lrgc-slam "
						  "--write-default-config FILE writes one with every key)");
	std::vector<std::string> allowed = TLRGCParams::sectionNames();
	allowed.push_back("LogReader");
	allowed.push_back("LiveMapping");
	allowed.push_back("Localization");
	rejectKeysBeforeTheFirstSection(path);
	try
	{
		// Inside the try: MRPT's parser throws on a malformed "${..}" / "$env{..}" /
		// "$eval{..}" (found by fuzz/fuzz_ini), which is a bad .ini like any other (exit 2),
		// not an error of the input log.
		const mrpt::config::CConfigFile ini(path);
		rejectUnknownSections(ini, allowed);
		cfg.warnings = cfg.lrgc.loadReportingRenames(ini, {});
		const auto current = withCurrentKeys(ini, appRenamedKeys(), {}, cfg.warnings);
		cfg.reader.loadFromConfigFile(current, "LogReader");
		cfg.live.loadFromConfigFile(current, "LiveMapping");
		cfg.localization.loadFromConfigFile(current, "Localization");
	}
	catch (const std::exception& e)
	{
		// "FILE:LINE: " where the offending key (or section) is written in the file; a value
		// checked against another key's may come from the defaults, and then has no line.
		std::string message = oneLineError(e);
		std::string where = path;
		if (const auto parsed = parserLineOf(message))  // MRPT's parser: "Line N: ..."
		{
			where += ":" + std::to_string(parsed->first);
			message = parsed->second;
		}
		else if (const auto place = paramPlaceOf(message))
			if (const auto line = lineOfKey(path, place->section, place->key))
				where += ":" + std::to_string(*line);
		throw CSetupError(
			where + ": " + message +
				"; lrgc-slam --write-default-config FILE writes every section and "
				"key with its unit and meaning",
			errorDetails(e));
	}
	return cfg;
}

TAppConfig loadAppConfig(const TSlamCommandLine& cl)
{
	TAppConfig cfg = loadAppConfig(cl.config);
	if (!cl.laser.empty()) cfg.lrgc.builder.laser_label = cl.laser;
	return cfg;
}

const std::vector<std::pair<std::string, std::string>>& userKeys()
{
	static const std::vector<std::pair<std::string, std::string>> keys = {
		{"MapBuilder", "laser_label"},
		{"MapBuilder", "min_range_m"},
		{"MapBuilder", "max_range_m"},
		{"MapBuilder", "scan_sweep_time_s"},
		{"MapBuilder", "keyframe_distance_m"},
		{"MapBuilder", "keyframe_angle_deg"},
		{"MapBuilder", "grid_resolution_m"},
		{"MapBuilder", "loop_closing"},
		{"MapBuilder", "final_optimization"},
		{"KeyframeReuse", "enabled"},
		{"MotionPredictor", "use_odometry"},
		{"MotionPredictor", "k_xy_m_per_m"},
		{"MotionPredictor", "k_xy_m_per_rad"},
		{"MotionPredictor", "k_phi_rad_per_m"},
		{"MotionPredictor", "k_phi_rad_per_rad"},
		{"LocalRegistration", "window_size"},
		{"LocalRegistration", "laser_only_window_size"},
		{"LoopCloser", "max_window_xy_m"},
		{"LoopCloser", "max_window_phi_deg"},
		{"LoopCloser", "background"},
		{"RevisitLinker", "enabled"},
		{"LogReader", "carmen_180_beams_fov_deg"},
		{"LogReader", "carmen_max_range_m"},
		{"LiveMapping", "save_interval_s"},
		{"LiveMapping", "max_backlog_scans"},
		{"LiveMapping", "sensor_timeout_s"},
		{"LiveMapping", "loop_results_when_ready"},
		{"Localization", "track_radius_m"},
		{"Localization", "lost_after"}};
	return keys;
}

std::string appConfigSections(const TAppConfig& cfg)
{
	mrpt::config::CConfigFileMemory mem;
	cfg.lrgc.saveToConfigFile(mem, {});
	cfg.reader.saveToConfigFile(mem, "LogReader");
	cfg.live.saveToConfigFile(mem, "LiveMapping");
	cfg.localization.saveToConfigFile(mem, "Localization");
	return mem.getContent();
}

namespace
{
// Every section and key of the app, as saveToConfigFile() writes them.
std::string allKeysText()
{
	return appConfigSections(TAppConfig{});
}

// The lines of an .ini text that set a key of `keep` (and the headers of their sections).
std::string onlyKeys(const std::string& text,
					 const std::vector<std::pair<std::string, std::string>>& keep)
{
	const std::set<std::pair<std::string, std::string>> wanted(keep.begin(), keep.end());
	std::string out, section;
	std::istringstream in(text);
	for (std::string line; std::getline(in, line);)
	{
		const std::string t = trimmed(line);
		if (!t.empty() && t[0] == '[')
		{
			section = trimmed(t.substr(1, t.find(']') - 1));
			const bool used = std::any_of(keep.begin(), keep.end(),
										  [&](const auto& k) { return k.first == section; });
			if (used) out += (out.empty() ? "" : "\n") + line + "\n";
			continue;
		}
		const size_t eq = t.find('=');
		if (eq != std::string::npos && wanted.count({section, trimmed(t.substr(0, eq))}))
			out += line + "\n";
	}
	return out;
}
}  // namespace

std::string defaultAppConfigText()
{
	return "# lrgc-slam's parameters for a new robot, generated by `lrgc-slam "
		   "--write-default-config FILE`.\n"
		   "# Units are in the key names (_m, _s, _deg, ...) and comments. Every other key "
		   "keeps its\n"
		   "# default: `lrgc-slam --write-default-config FILE --expert` writes all of them\n"
		   "# (share/lrgc/lrgc-expert.ini); doc/parameters.md says why each has its value.\n" +
		   onlyKeys(allKeysText(), userKeys());
}

std::string expertAppConfigText()
{
	return "# Every lrgc-slam parameter, generated by `lrgc-slam --write-default-config FILE "
		   "--expert`.\n"
		   "# Units are in the key names (_m, _s, _deg, ...) and comments; doc/parameters.md "
		   "says why\n"
		   "# each has its value. A user's few are in share/lrgc/lrgc-default.ini.\n" +
		   allKeysText();
}

}  // namespace lrgc::apps
