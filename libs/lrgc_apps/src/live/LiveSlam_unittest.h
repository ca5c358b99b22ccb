/* Helpers shared by the in-process CLiveSlam tests (LiveSlam_unittest.cpp,
 * LiveSlamSavedMap_unittest.cpp): reading what a live run wrote. */
#pragma once

#include <fstream>
#include <regex>
#include <string>
#include <vector>

namespace lrgc::apps::live_test
{
/** The integer after "key": in a JSON text (live.json, stats.json); -1 if absent. */
inline long jsonInt(const std::string& json, const std::string& key)
{
	std::smatch m;
	if (!std::regex_search(json, m, std::regex("\"" + key + "\": (-?[0-9]+)"))) return -1;
	return std::stol(m[1]);
}

/** The lines of a text file (none if it cannot be read). */
inline std::vector<std::string> lines(const std::string& path)
{
	std::ifstream f(path);
	std::vector<std::string> out;
	for (std::string l; std::getline(f, l);) out.push_back(l);
	return out;
}
}  // namespace lrgc::apps::live_test
