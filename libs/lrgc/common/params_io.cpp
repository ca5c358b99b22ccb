#include <lrgc/common/params_io.h>

#include <mrpt/core/bits_math.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/system/string_utils.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>
#include <optional>
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

// The value of `key` as written, without surrounding blanks and a trailing "// comment"
// (the default .ini has one on every line); nullopt if the section has no such key.
std::optional<std::string> rawValue(const mrpt::config::CConfigFileBase& c,
									const std::string& section, const std::string& key)
{
	static const std::string kAbsent = "\x01(absent)\x01";
	std::string v = c.read_string(section, key, kAbsent);
	if (v == kAbsent) return std::nullopt;
	if (const size_t comment = v.find("//"); comment != std::string::npos) v.erase(comment);
	return mrpt::system::trim(v);
}

[[noreturn]] void throwBadValue(const std::string& section, const std::string& key,
								const std::string& value, const char* expected)
{
	THROW_EXCEPTION_FMT("Invalid value for [%s] %s: '%s' is not %s", section.c_str(),
						key.c_str(), value.c_str(), expected);
}

// The whole of `v` as one T (an optional leading '+' allowed), or nullopt.
template <typename T>
std::optional<T> parseWhole(const std::string& v)
{
	const char* first = v.data();
	const char* const last = v.data() + v.size();
	if (first != last && *first == '+' && last - first > 1 && first[1] != '-') ++first;
	T x{};
	const auto [end, ec] = std::from_chars(first, last, x);
	if (first == last || ec != std::errc() || end != last) return std::nullopt;
	return x;
}
}  // namespace

double readDouble(const mrpt::config::CConfigFileBase& c, const std::string& section,
				  const std::string& key, double current)
{
	const auto raw = rawValue(c, section, key);
	if (!raw) return current;
	const auto x = parseWhole<double>(*raw);
	if (!x || !std::isfinite(*x))
		throwBadValue(section, key, *raw,
					  "a number (expected a decimal number such as 0.5 or 1e-3)");
	return *x;
}

double readDegrees(const mrpt::config::CConfigFileBase& c, const std::string& section,
				   const std::string& key, double currentRad)
{
	// An absent key keeps currentRad itself (not DEG2RAD(RAD2DEG(currentRad)), which may
	// differ in the last bit).
	if (!rawValue(c, section, key)) return currentRad;
	return mrpt::DEG2RAD(readDouble(c, section, key, 0.0));
}

int readInt(const mrpt::config::CConfigFileBase& c, const std::string& section,
			const std::string& key, int current)
{
	const auto raw = rawValue(c, section, key);
	if (!raw) return current;
	const auto x = parseWhole<int>(*raw);
	if (!x)
		throwBadValue(section, key, *raw, "a whole number (expected an integer such as 20)");
	return *x;
}

size_t readCount(const mrpt::config::CConfigFileBase& c, const std::string& section,
				 const std::string& key, size_t current)
{
	const auto raw = rawValue(c, section, key);
	if (!raw) return current;
	const auto x = parseWhole<unsigned long long>(*raw);
	if (!x || *x > std::numeric_limits<size_t>::max())
		throwBadValue(section, key, *raw, "a whole number >= 0 (expected a count such as 7)");
	return static_cast<size_t>(*x);
}

bool readBool(const mrpt::config::CConfigFileBase& c, const std::string& section,
			  const std::string& key, bool current)
{
	const auto raw = rawValue(c, section, key);
	if (!raw) return current;
	std::string v = *raw;
	std::transform(v.begin(), v.end(), v.begin(),
				   [](unsigned char ch) { return std::tolower(ch); });
	if (v == "true" || v == "yes" || v == "1") return true;
	if (v == "false" || v == "no" || v == "0") return false;
	throwBadValue(section, key, *raw, "a boolean (expected true, false, yes, no, 1 or 0)");
}

std::string readString(const mrpt::config::CConfigFileBase& c, const std::string& section,
					   const std::string& key, const std::string& current)
{
	const auto raw = rawValue(c, section, key);
	return raw ? *raw : current;
}

void rejectUnknownKeys(const mrpt::config::CLoadableOptions& knownKeysFrom,
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
		THROW_EXCEPTION_FMT("Unknown key '%s' in section [%s]%s", key.c_str(), section.c_str(),
							hint.c_str());
	}
}

namespace
{
// The shortest "%.{p}g" text of v whose value x gives back `target` through `back(x)`.
template <typename Back>
std::string shortestText(double v, double target, Back back)
{
	// At least as many digits as the integer part has, so that 50 is "50", not "5e+01".
	const int intDigits =
		std::abs(v) >= 1 ? std::min(17, int(std::floor(std::log10(std::abs(v)))) + 1) : 1;
	for (int p = intDigits; p <= 17; ++p)
	{
		const std::string text = mrpt::format("%.*g", p, v);
		const auto x = parseWhole<double>(text);
		if (x && back(*x) == target) return text;
	}
	return mrpt::format("%.17g", v);
}

void writeText(mrpt::config::CConfigFileBase& c, const std::string& section,
			   const std::string& key, const std::string& text, const std::string& comment)
{
	c.write(section, key, text, mrpt::config::MRPT_SAVE_NAME_PADDING(),
			mrpt::config::MRPT_SAVE_VALUE_PADDING(), comment);
}
}  // namespace

std::string exactDecimal(double v)
{
	return shortestText(v, v, [](double x) { return x; });
}

void writeValue(mrpt::config::CConfigFileBase& c, const std::string& section,
				const std::string& key, double v, const std::string& comment)
{
	writeText(c, section, key, exactDecimal(v), comment);
}

void writeValue(mrpt::config::CConfigFileBase& c, const std::string& section,
				const std::string& key, int v, const std::string& comment)
{
	writeText(c, section, key, std::to_string(v), comment);
}

void writeValue(mrpt::config::CConfigFileBase& c, const std::string& section,
				const std::string& key, uint64_t v, const std::string& comment)
{
	writeText(c, section, key, std::to_string(v), comment);
}

void writeValue(mrpt::config::CConfigFileBase& c, const std::string& section,
				const std::string& key, bool v, const std::string& comment)
{
	writeText(c, section, key, v ? "true" : "false", comment);
}

void writeValue(mrpt::config::CConfigFileBase& c, const std::string& section,
				const std::string& key, const std::string& v, const std::string& comment)
{
	writeText(c, section, key, v, comment);
}

void writeDegrees(mrpt::config::CConfigFileBase& c, const std::string& section,
				  const std::string& key, double rad, const std::string& comment)
{
	writeText(c, section, key,
			  shortestText(mrpt::RAD2DEG(rad), rad, [](double d) { return mrpt::DEG2RAD(d); }),
			  comment);
}

mrpt::config::CConfigFileMemory withCurrentKeys(const mrpt::config::CConfigFileBase& c,
												const std::vector<TRenamedKey>& renames,
												const std::string& prefix,
												std::vector<std::string>& warnings)
{
	mrpt::config::CConfigFileMemory out;
	std::vector<std::string> sections;
	c.getAllSections(sections);
	for (const auto& section : sections)
	{
		std::vector<std::string> keys;
		c.getAllKeys(section, keys);
		std::set<std::string> present;
		for (const auto& k : keys) present.insert(mrpt::system::trim(k));
		for (const auto& rawKey : keys)
		{
			const std::string key = mrpt::system::trim(rawKey);
			std::string name = key;
			for (const auto& r : renames)
			{
				if (prefix + r.section != section || r.oldKey != key) continue;
				const std::string old = "[" + section + "] " + key;
				if (r.newKey.empty())
				{
					warnings.push_back(old + " is no longer a key: ignored (" + r.why + ")");
					name.clear();
					break;
				}
				if (present.count(r.newKey))
					THROW_EXCEPTION_FMT(
						"Invalid value for [%s] %s: set twice, also under its old name %s",
						section.c_str(), r.newKey.c_str(), key.c_str());
				warnings.push_back(
					old + " is now " + r.newKey +
					"; read as such (lrgc-slam --write-default-config FILE writes the current "
					"names)");
				name = r.newKey;
				break;
			}
			if (!name.empty()) out.write(section, name, c.read_string(section, rawKey, ""));
		}
	}
	return out;
}

std::optional<TParamPlace> paramPlaceOf(const std::string& message)
{
	// The formats of throwBadValue()/requireParam(), rejectUnknownKeys() and
	// rejectUnknownSections() (MapBuilderParams.cpp).
	const auto between = [&](size_t from, char open, char close) -> std::optional<std::string>
	{
		const size_t a = message.find(open, from);
		const size_t b = a == std::string::npos ? a : message.find(close, a + 1);
		if (b == std::string::npos) return std::nullopt;
		return message.substr(a + 1, b - a - 1);
	};
	const std::string invalid = "Invalid value for [", unknownKey = "Unknown key '",
					  unknownSection = "Unknown section [";
	if (const size_t at = message.find(invalid); at != std::string::npos)
	{
		const auto section = between(at, '[', ']');
		const size_t keyFrom = message.find("] ", at);
		const size_t keyEnd =
			keyFrom == std::string::npos ? keyFrom : message.find(':', keyFrom);
		if (!section || keyEnd == std::string::npos) return std::nullopt;
		return TParamPlace{*section, message.substr(keyFrom + 2, keyEnd - keyFrom - 2)};
	}
	if (const size_t at = message.find(unknownKey); at != std::string::npos)
	{
		const auto key = between(at, '\'', '\'');
		const size_t in = message.find("in section [", at);
		const auto section = in == std::string::npos ? std::nullopt : between(in, '[', ']');
		if (!key || !section) return std::nullopt;
		return TParamPlace{*section, *key};
	}
	if (const size_t at = message.find(unknownSection); at != std::string::npos)
		if (const auto section = between(at, '[', ']')) return TParamPlace{*section, ""};
	return std::nullopt;
}

void requireParam(bool ok, const std::string& section, const std::string& key,
				  const std::string& what)
{
	if (!ok)
		THROW_EXCEPTION_FMT("Invalid value for [%s] %s: %s", section.c_str(), key.c_str(),
							what.c_str());
}

}  // namespace lrgc
