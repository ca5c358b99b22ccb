/* Atomic output files: every output of lrgc-slam is written to a temporary file in the same
 * directory and then renamed over the destination (rename(2) is atomic within a file
 * system), so a reader never sees a half-written map, and a crash or Ctrl-C mid-write leaves
 * the previous version intact.
 *
 * A full disk must not publish a short file either. Library streams do not say when their
 * last flush fails (MRPT's CFileGZOutputStream ignores gzclose()'s result, std::ofstream's
 * close() leaves only a fail bit, stdio's fclose() flushes through an internal write), so every
 * byte goes through write(2) here, each call checked, then fsync(2) and close(2), both checked,
 * before the rename. On any failure the temporary is removed, the destination keeps its old
 * content, and the error names the destination and the cause ("No space left on device"). */
#pragma once

#include <functional>
#include <string>
#include <string_view>

namespace mrpt::serialization
{
class CArchive;
}

namespace lrgc::apps
{
/** Calls `writer(tmpPath)`, which must create and close tmpPath, then fsyncs and renames it
 * to `path`. On any exception the temporary file is removed and the exception rethrown.
 * The writer must check its own writes: prefer the two functions below, which do. */
void writeFileAtomically(const std::string& path,
						 const std::function<void(const std::string& tmpPath)>& writer);

/** Atomically writes `contents` to `path`, every write, the fsync and the close checked. */
void writeTextFileAtomically(const std::string& path, std::string_view contents);

/** Compression of writeArchiveAtomically's file. */
enum class TFileCompression
{
	None,
	Gzip  //!< gzip level 1, as MRPT's CFileGZOutputStream writes .gz and .rawlog files
};

/** Atomically writes what `writer` puts in the MRPT archive it is given (plain or gzip), with
 * every write, the final deflate, the fsync and the close checked. */
void writeArchiveAtomically(const std::string& path, TFileCompression compression,
							const std::function<void(mrpt::serialization::CArchive&)>& writer);

}  // namespace lrgc::apps
