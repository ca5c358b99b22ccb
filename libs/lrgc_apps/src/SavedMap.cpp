#include "lrgc_apps/SavedMap.h"

#include "ErrorText.h"

#include "lrgc_apps/io/SimplemapFile.h"

#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace lrgc::apps
{
TSavedMap loadSavedMap(const std::string& path, const std::string& option)
{
	namespace fs = std::filesystem;
	std::error_code ec;
	TSavedMap out;
	out.path = path;
	if (!fs::exists(path, ec))
		throw std::runtime_error(option + " '" + path +
								 "': no such file or folder; name an lrgc output folder or "
								 "a .simplemap(.gz) file");
	if (!fs::is_directory(path, ec))
	{
		out.keyframes = readSimplemapFile(path, option);
		return out;
	}
	const std::string simplemap = (fs::path(path) / kSimplemapFile).string();
	if (!fs::exists(simplemap, ec))
		throw std::runtime_error(option + " '" + path + "': the folder has no " +
								 kSimplemapFile + " (is it an lrgc output folder?)");
	out.keyframes = readSimplemapFile(simplemap, option);
	const std::string graphFile = (fs::path(path) / kPoseGraphFile).string();
	if (!fs::exists(graphFile, ec)) return out;  // an older output folder: keyframes only
	std::ifstream in(graphFile);
	if (!in) throw std::runtime_error(option + " '" + graphFile + "': cannot open it");
	try
	{
		out.graph = poseGraphFromText(in, graphFile);
	}
	catch (const std::exception& e)
	{
		throw std::runtime_error(option + ": " + oneLineError(e));
	}
	if (out.graph->graph.numNodes() != out.keyframes.size())
		throw std::runtime_error(option + " '" + path + "': " + kPoseGraphFile + " has " +
								 std::to_string(out.graph->graph.numNodes()) + " nodes but " +
								 kSimplemapFile + " " + std::to_string(out.keyframes.size()) +
								 " keyframes: the files are of different runs");
	if (!out.graph->warning.empty()) out.warnings.push_back(option + ": " + out.graph->warning);
	return out;
}

void initializeFromSavedMap(CMetricMapBuilderLRGC& builder, const TSavedMap& map)
{
	if (map.graph)
		builder.initialize(map.keyframes, map.graph->graph, map.graph->laserLabel,
						   map.graph->sessions);
	else
		builder.initialize(map.keyframes);
	if (builder.graph().numNodes() == 0)
		throw std::runtime_error("'" + map.path +
								 "': no keyframe of the map has a usable 2D laser scan");
}

}  // namespace lrgc::apps
