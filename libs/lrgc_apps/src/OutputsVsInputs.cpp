#include "OutputsVsInputs.h"

#include <sys/stat.h>

#include <filesystem>

namespace lrgc::apps
{
bool samePath(const std::string& a, const std::string& b)
{
	struct stat sa
	{
	}, sb{};
	if (::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0)
		return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
	namespace fs = std::filesystem;
	std::error_code ea, eb;
	const fs::path ca = fs::weakly_canonical(fs::absolute(a, ea), ea);
	const fs::path cb = fs::weakly_canonical(fs::absolute(b, eb), eb);
	return !ea && !eb && ca == cb;
}

std::string outputOverInput(const std::vector<TNamedPath>& outputs,
							const std::vector<TNamedPath>& inputs)
{
	for (const TNamedPath& out : outputs)
		for (const TNamedPath& in : inputs)
			if (!out.path.empty() && !in.path.empty() && samePath(out.path, in.path))
				return out.option + " '" + out.path + "' is " + in.option + " '" + in.path +
					   "' (the same file): an output is never written over an input; name "
					   "another " +
					   out.option;
	return {};
}

}  // namespace lrgc::apps

#include "CommandLine.h"
#include "lrgc_apps/SavedMap.h"

namespace lrgc::apps
{
namespace
{
// Every name lrgc-slam writes into --out, in any mode (offline, --localize, --live).
const char* const kSlamOutputNames[] = {"map.gridmap.gz", "map.png",          "map.pgm",
										"map.yaml",       "map.simplemap.gz", "trajectory.tum",
										"graph.graph",    "graph.lrgc",       "timing.csv",
										"stats.json",     "capture.rawlog",   "live.json"};

// A saved map is read from the file itself, or from a folder's two files.
void addSavedMap(std::vector<TNamedPath>& inputs, const std::string& option,
				 const std::string& map)
{
	if (map.empty()) return;
	inputs.push_back({option, map});
	namespace fs = std::filesystem;
	if (!fs::is_directory(map)) return;
	inputs.push_back({option, (fs::path(map) / kSimplemapFile).string()});
	inputs.push_back({option, (fs::path(map) / kPoseGraphFile).string()});
}

// An output name already taken by a folder or a non-regular file (DIR/map.png/): the rename
// at the end of the run would fail, after the mapping, and the outputs after it be lost.
std::string outputNameTaken(const std::vector<TNamedPath>& outputs)
{
	namespace fs = std::filesystem;
	for (const TNamedPath& out : outputs)
	{
		std::error_code ec;
		const auto st = fs::symlink_status(out.path, ec);
		if (out.path.empty() || ec || !fs::exists(st) || fs::is_regular_file(st) ||
			fs::is_symlink(st))  // rename(2) replaces a link, whatever it points to
			continue;
		return out.option + ": '" + out.path + "' exists and is " +
			   (fs::is_directory(st) ? "a folder" : "not a regular file") +
			   "; an output is written there: move it away, or name another " + out.option;
	}
	return {};
}

// The folder --localize reads its map from: MAP itself, or the folder MAP is in.
std::string mapFolder(const std::string& map)
{
	namespace fs = std::filesystem;
	if (fs::is_directory(map)) return map;
	const fs::path parent = fs::path(map).parent_path();
	return parent.empty() ? "." : parent.string();
}
}  // namespace

std::string slamOutputOverInput(const TSlamCommandLine& cl)
{
	if (!cl.localize.empty() && !cl.outDir.empty() &&
		samePath(cl.outDir, mapFolder(cl.localize)))
		return "--out '" + cl.outDir + "' is the folder of --localize '" + cl.localize +
			   "': --localize never writes into the map's folder (an output is never written "
			   "over an "
			   "input); name another --out";
	std::vector<TNamedPath> inputs = {
		{"--input", cl.input}, {"--config", cl.config}, {"--live", cl.live}};
	addSavedMap(inputs, "--initial-map", cl.initialMap);
	addSavedMap(inputs, "--localize", cl.localize);
	addSavedMap(inputs, "--merge", cl.mergeA);
	addSavedMap(inputs, "--merge", cl.mergeB);
	std::vector<TNamedPath> outputs = {{"--save-rawlog", cl.saveRawlog}};
	if (!cl.outDir.empty())
		for (const char* name : kSlamOutputNames)
			outputs.push_back({"--out", (std::filesystem::path(cl.outDir) / name).string()});
	if (std::string clash = outputOverInput(outputs, inputs); !clash.empty()) return clash;
	return outputNameTaken(outputs);
}

}  // namespace lrgc::apps
