/* The .ini of lrgc-slam: the LRGC stages' sections (TLRGCParams), [LogReader] and, for
 * --live runs, [LiveMapping]. Unknown sections and keys, values that are not of the key's
 * type (params_io.h) and values out of range are errors (CSetupError naming the file, the line
 * where the key or section is written, the section and the key). */
#pragma once

#include <lrgc/localization/LocalizationParams.h>
#include <lrgc/map_builder/MapBuilderParams.h>
#include "LiveMappingParams.h"
#include <lrgc_apps/io/LogReader.h>

#include <optional>
#include <utility>
#include <string>
#include <vector>

namespace lrgc::apps
{
struct TAppConfig
{
	TLRGCParams lrgc;
	TLogReaderOptions reader;
	TLiveMappingParams live;           //!< only used by --live
	TLocalizationParams localization;  //!< [Localization]: --initial-map, --localize
	/** One line per key of the .ini read under an old name ("[MapBuilder] keyframe_distance
	 * is now keyframe_distance_m; ..."), for the app to report as warnings. */
	std::vector<std::string> warnings;
};

/** The keys of the app's own sections renamed since an earlier lrgc (still read); the
 * stages' are TLRGCParams::renamedKeys(). */
const std::vector<lrgc::TRenamedKey>& appRenamedKeys();

struct TSlamCommandLine;

/** --config's .ini (as below), then the command line's overrides of it: --laser LABEL sets
 * [MapBuilder] laser_label. */
TAppConfig loadAppConfig(const TSlamCommandLine& cl);

/** Defaults when `path` is empty; throws CUsageError on a missing file, CSetupError on a bad
 * section, key or value. */
TAppConfig loadAppConfig(const std::string& path);

/** Whether two .ini section or key names are the same name: as MRPT's CConfigFile compares
 * them, without letter case (checked on MRPT 2.5.8). */
bool sameIniName(const std::string& a, const std::string& b);

/** The 1-based line of `path` that sets `key` in `section` (the last one: MRPT's CConfigFile
 * reads the last of repeated keys), or, for an empty `key`, the first that opens `section`;
 * names compare as CConfigFile's do, without letter case (both checked on MRPT 2.5.8).
 * MRPT's readers keep no line numbers: this scans the text, for error messages. */
std::optional<size_t> iniLineOf(const std::string& path, const std::string& section,
								const std::string& key);

/** The .ini a user starts from (lrgc-slam --write-default-config, share/lrgc/lrgc-default.ini):
 * the keys of userKeys() only, with their default values, units and meanings, generated from
 * the parameter structs' saveToConfigFile(). */
std::string defaultAppConfigText();
/** Every key (lrgc-slam --write-default-config FILE --expert, share/lrgc/lrgc-expert.ini);
 * doc/parameters.md says why each has its value. */
std::string expertAppConfigText();
/** The keys a user of a new robot sets (sensor, odometry, map output, the accuracy / speed
 * trade, live runs), as {section, key}; at most 40. Every other key keeps its default
 * unless an .ini sets it. */
const std::vector<std::pair<std::string, std::string>>& userKeys();

/** Every section and key of `cfg`, as defaultAppConfigText() writes the defaults: the
 * config.ini of an output folder (RunConfigFile.h). */
std::string appConfigSections(const TAppConfig& cfg);

}  // namespace lrgc::apps
