/* config.ini, written into every output folder: the configuration a run used, every section
 * and key with the value used (the --config .ini over the defaults, --laser applied), in the
 * text `lrgc-slam --write-default-config` writes, so that
 *   lrgc-slam --input LOG --config OUT/config.ini --out OUT2
 * repeats the run. It is made by the parameter structs' own saveToConfigFile()
 * (appConfigSections), so it follows them as they change. */
#pragma once

#include <string>

namespace lrgc::apps
{
struct TAppConfig;

/** The name of the file in the output folder. */
inline constexpr const char* kRunConfigFile = "config.ini";

/** config.ini's text for a run of `input` (a log file, or the sensors .ini of a live run). */
std::string runConfigText(const TAppConfig& cfg, const std::string& input);

}  // namespace lrgc::apps
