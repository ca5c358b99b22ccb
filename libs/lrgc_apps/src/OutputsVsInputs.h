/* No program writes over one of its inputs (issue 30). Paths are compared by identity, not by
 * name: two existing paths are the same file when their device and inode agree (symbolic
 * links, "./", "..", hard links and bind mounts all see through), a path not yet existing by
 * its absolute, normalised form with the existing part of it resolved (weakly_canonical).
 * Checked before any work, so that a refused run has read and written nothing. */
#pragma once

#include <string>
#include <vector>

namespace lrgc::apps
{
/** A path as the user named it: the option that named it ("--input") and the path. */
struct TNamedPath
{
	std::string option;
	std::string path;
};

/** True if `a` and `b` name the same file or directory (see above). */
bool samePath(const std::string& a, const std::string& b);

/** The one-line reason why an output would be written over an input ("--out 'D/x.tum' is
 * --trajectory 'x.tum' (the same file): an output is never written over an input; name
 * another"), or an empty string when no output is an input. Empty paths are skipped. */
std::string outputOverInput(const std::vector<TNamedPath>& outputs,
							const std::vector<TNamedPath>& inputs);

}  // namespace lrgc::apps

namespace lrgc::apps
{
struct TSlamCommandLine;

/** lrgc-slam's check: no file it may write into --out (every name it writes there, in any
 * mode) or --save-rawlog is --input, --config, --live, or a file of --initial-map/--localize
 * (the map file, or a map folder's graph.lrgc and map.simplemap.gz); --localize never writes
 * into the map's folder; and no name it writes into --out is taken by a folder or another
 * non-regular file (found before the run, not at its end). The one-line reason, or empty. */
std::string slamOutputOverInput(const TSlamCommandLine& cl);

}  // namespace lrgc::apps
