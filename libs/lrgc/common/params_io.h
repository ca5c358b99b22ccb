/* Helpers shared by every T...Params struct of lrgc.
 *
 * Each stage's parameters derive from mrpt::config::CLoadableOptions and are loaded from and
 * saved to one .ini section in MRPT's way. The set of valid keys of a section is defined by
 * saveToConfigFile() itself: rejectUnknownKeys() saves a default-constructed copy into memory
 * and compares key sets, so load and save can never drift apart and a misspelt key is an error
 * instead of a silently ignored line.
 *
 * Values are read strictly by readDouble(), readInt(), readCount() and readBool(), which every
 * loader uses instead of CConfigFileBase::read_double() and friends: MRPT's readers take
 * `abc` and `0,5` for 0, `on` and `maybe` for false and `2.5` for 2 without a word, which turns
 * a typo into a wrong run or into a range error blamed on the value 0.
 *
 * Values are written by writeValue() and writeDegrees(), which every saver uses instead of
 * CConfigFileBase::write(): a number is written as the shortest decimal text that reads back
 * to the same double (MRPT writes "%f" / "%e", six decimals: 0.00012345 came back 0.000123),
 * so save -> load -> save is the identity.
 *
 * Names: the C++ field is named as its key. Memory holds SI units and radians; a key whose
 * value is in degrees ends in _deg and its field is the key without _deg (key
 * max_window_phi_deg, field max_window_phi [rad]). Every other dimensioned key ends in its
 * unit (_m, _s, _ms, _keyframes, _deg_per_s, ...); a fraction in [0, 1] is a *_fraction.
 */
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/config/CLoadableOptions.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace lrgc
{
/** Throws (mrpt::ExceptionWithCallBackBase via THROW_EXCEPTION) if `source` has, in
 * `section`, a key that `knownKeysFrom.saveToConfigFile()` does not write. The message names
 * the section, the key, and the closest valid key. */
void rejectUnknownKeys(const mrpt::config::CLoadableOptions& knownKeysFrom,
					   const mrpt::config::CConfigFileBase& source, const std::string& section);

/** Strict readers of one key of `section`. A key that is absent keeps `current`. A present
 * value (blanks and a trailing `// comment` aside) must be one whole value of the type, else
 * they throw naming the section, the key, the value and the type expected, e.g.
 * "Invalid value for [MapBuilder] keyframe_distance_m: 'abc' is not a number (expected a
 * decimal number such as 0.5 or 1e-3)". */
/** A finite decimal number ("0.5", "-2", "1e-3"; not "0,5", "inf", "abc"). */
double readDouble(const mrpt::config::CConfigFileBase& c, const std::string& section,
				  const std::string& key, double current);
/** An angle whose key is in degrees (by convention its name ends in _deg), kept in radians:
 * `current` and the result are [rad]. */
double readDegrees(const mrpt::config::CConfigFileBase& c, const std::string& section,
				   const std::string& key, double currentRad);
/** A whole number that fits an int ("7", "-1"; not "2.5", "7.0", "1e3"). */
int readInt(const mrpt::config::CConfigFileBase& c, const std::string& section,
			const std::string& key, int current);
/** A whole number >= 0 (a count or a size). */
size_t readCount(const mrpt::config::CConfigFileBase& c, const std::string& section,
				 const std::string& key, size_t current);
/** true, false, yes, no, 1 or 0, in any letter case ("on" and "maybe" are errors). */
bool readBool(const mrpt::config::CConfigFileBase& c, const std::string& section,
			  const std::string& key, bool current);
/** A string: the value as written, blanks and a trailing `// comment` aside (may be empty). */
std::string readString(const mrpt::config::CConfigFileBase& c, const std::string& section,
					   const std::string& key, const std::string& current);

/** The shortest decimal text ("%.{p}g", p = 1..17; no exponent for 1 <= |v| < 1e17) that
 * reads back as exactly v. */
std::string exactDecimal(double v);

/** Writers of one key: `key = value // comment`, numbers written exactly (exactDecimal). */
void writeValue(mrpt::config::CConfigFileBase& c, const std::string& section,
				const std::string& key, double v, const std::string& comment);
void writeValue(mrpt::config::CConfigFileBase& c, const std::string& section,
				const std::string& key, int v, const std::string& comment);
void writeValue(mrpt::config::CConfigFileBase& c, const std::string& section,
				const std::string& key, uint64_t v, const std::string& comment);
void writeValue(mrpt::config::CConfigFileBase& c, const std::string& section,
				const std::string& key, bool v, const std::string& comment);
void writeValue(mrpt::config::CConfigFileBase& c, const std::string& section,
				const std::string& key, const std::string& v, const std::string& comment);
/** Text literals: without this overload they would convert to bool. */
inline void writeValue(mrpt::config::CConfigFileBase& c, const std::string& section,
					   const std::string& key, const char* v, const std::string& comment)
{
	writeValue(c, section, key, std::string(v), comment);
}
/** An angle held in radians, written in degrees (key ending in _deg): the shortest decimal
 * d such that readDegrees() gives back exactly `rad` (DEG2RAD(d) == rad). */
void writeDegrees(mrpt::config::CConfigFileBase& c, const std::string& section,
				  const std::string& key, double rad, const std::string& comment);

/** A key an earlier lrgc wrote under another name, still read under it (issue 27: units in
 * key names, one name per concept). newKey empty: no longer a key; its value is ignored. */
struct TRenamedKey
{
	std::string section, oldKey, newKey;
	std::string why;  //!< newKey empty: why the key is gone, for the warning
};

/** A copy of `c` with every key of `renames` written under its old name (in section
 * prefix + section) moved to its new name, and one warning per such key, e.g. "[MapBuilder]
 * keyframe_distance is now keyframe_distance_m; read as such (lrgc-slam --write-default-config
 * FILE writes the current names)". Both names in one section is an error naming both. */
mrpt::config::CConfigFileMemory withCurrentKeys(const mrpt::config::CConfigFileBase& c,
												const std::vector<TRenamedKey>& renames,
												const std::string& prefix,
												std::vector<std::string>& warnings);

/** The section and key an error message of these functions (or of rejectUnknownSections())
 * is about, so that a caller holding the .ini text can point at its line: "Invalid value for
 * [S] K: ...", "Unknown key 'K' in section [S]..." give {S, K}; "Unknown section [S]..."
 * gives {S, ""}. nullopt for any other message. */
struct TParamPlace
{
	std::string section, key;  //!< key empty: the section itself
};
std::optional<TParamPlace> paramPlaceOf(const std::string& message);

/** Throws with a message naming section and key if `ok` is false. For validation on load. */
void requireParam(bool ok, const std::string& section, const std::string& key,
				  const std::string& what);

}  // namespace lrgc
