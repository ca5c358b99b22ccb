/* The .ini of lrgc-slam: the LRGC stages' sections (TLRGCParams), [LogReader] and, for
 * --live runs, [LiveMapping]. Unknown sections and keys, values that are not of the key's
 * type (params_io.h) and values out of range are errors (CSetupError naming the file, section
 * and key). */
#pragma once

#include <lrgc/localization/LocalizationParams.h>
#include <lrgc/map_builder/MapBuilderParams.h>
#include <lrgc_apps/LiveMappingParams.h>
#include <lrgc_apps/io/LogReader.h>

#include <string>

namespace lrgc::apps
{
struct TAppConfig
{
	TLRGCParams lrgc;
	TLogReaderOptions reader;
	TLiveMappingParams live;  //!< only used by --live
	TLocalizationParams localization;  //!< [Localization]: --initial-map, --localize
};

/** Defaults when `path` is empty; throws CUsageError on a missing file, CSetupError on a bad
 * section, key or value. */
TAppConfig loadAppConfig(const std::string& path);

/** The default .ini, generated from the parameter structs' saveToConfigFile(). */
std::string defaultAppConfigText();

}  // namespace lrgc::apps
