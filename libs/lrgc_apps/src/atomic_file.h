/* Atomic output files: every output of lrgc-slam is written to a temporary file in the same
 * directory and then renamed over the destination (rename(2) is atomic within a file
 * system), so a reader never sees a half-written map, and a crash or Ctrl-C mid-write leaves
 * the previous version intact. */
#pragma once

#include <functional>
#include <string>

namespace lrgc::apps
{
/** Calls `writer(tmpPath)`, which must create and close tmpPath, then fsyncs and renames it
 * to `path`. On any exception the temporary file is removed and the exception rethrown. */
void writeFileAtomically(
	const std::string& path, const std::function<void(const std::string& tmpPath)>& writer);

/** Convenience: atomically writes `contents` to `path`. */
void writeTextFileAtomically(const std::string& path, const std::string& contents);

}  // namespace lrgc::apps
