/* The one JSON string escape of the apps' JSON outputs (stats.json, lrgc-eval --json, the
 * live and localisation reports). */
#pragma once

#include <string>

namespace lrgc::apps
{
/** `s` as a JSON string literal, quoted, with " \\ and control characters escaped. */
std::string jsonString(const std::string& s);
}  // namespace lrgc::apps
