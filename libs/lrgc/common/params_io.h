/* Helpers shared by every T...Params struct of lrgc.
 *
 * Each stage's parameters derive from mrpt::config::CLoadableOptions and are loaded from and
 * saved to one .ini section in MRPT's way. The set of valid keys of a section is defined by
 * saveToConfigFile() itself: rejectUnknownKeys() saves a default-constructed copy into memory
 * and compares key sets, so load and save can never drift apart and a misspelt key is an error
 * instead of a silently ignored line.
 */
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/config/CLoadableOptions.h>

#include <string>

namespace lrgc
{
/** Throws (mrpt::ExceptionWithCallBackBase via THROW_EXCEPTION) if `source` has, in
 * `section`, a key that `knownKeysFrom.saveToConfigFile()` does not write. The message names
 * the section, the key, and the closest valid key. */
void rejectUnknownKeys(
	const mrpt::config::CLoadableOptions& knownKeysFrom,
	const mrpt::config::CConfigFileBase& source, const std::string& section);

/** Throws with a message naming section and key if `ok` is false. For validation on load. */
void requireParam(
	bool ok, const std::string& section, const std::string& key, const std::string& what);

}  // namespace lrgc
