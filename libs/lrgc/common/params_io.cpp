#include <lrgc/common/params_io.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/system/string_utils.h>

#include <algorithm>
#include <set>
#include <vector>

namespace lrgc
{
namespace
{
// Levenshtein distance, to suggest the intended key for a misspelt one.
size_t editDistance(const std::string& a, const std::string& b)
{
	std::vector<size_t> row(b.size() + 1);
	for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
	for (size_t i = 1; i <= a.size(); ++i)
	{
		size_t diag = row[0];
		row[0] = i;
		for (size_t j = 1; j <= b.size(); ++j)
		{
			const size_t up = row[j];
			row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] != b[j - 1])});
			diag = up;
		}
	}
	return row[b.size()];
}
}  // namespace

void rejectUnknownKeys(
	const mrpt::config::CLoadableOptions& knownKeysFrom,
	const mrpt::config::CConfigFileBase& source, const std::string& section)
{
	mrpt::config::CConfigFileMemory mem;
	knownKeysFrom.saveToConfigFile(mem, section);
	std::vector<std::string> known, given;
	mem.getAllKeys(section, known);
	source.getAllKeys(section, given);
	// CConfigFileBase::write() with a name padding stores the key padded with blanks:
	// compare trimmed keys.
	for (auto& k : known) k = mrpt::system::trim(k);
	const std::set<std::string> knownSet(known.begin(), known.end());
	for (const auto& rawKey : given)
	{
		const std::string key = mrpt::system::trim(rawKey);
		if (knownSet.count(key)) continue;
		std::string best;
		size_t bestDist = 1000;
		for (const auto& k : known)
			if (const size_t d = editDistance(key, k); d < bestDist) bestDist = d, best = k;
		const std::string hint = best.empty() ? "" : " (did you mean '" + best + "'?)";
		THROW_EXCEPTION_FMT(
			"Unknown key '%s' in section [%s]%s", key.c_str(), section.c_str(), hint.c_str());
	}
}

void requireParam(
	bool ok, const std::string& section, const std::string& key, const std::string& what)
{
	if (!ok)
		THROW_EXCEPTION_FMT(
			"Invalid value for [%s] %s: %s", section.c_str(), key.c_str(), what.c_str());
}

}  // namespace lrgc
