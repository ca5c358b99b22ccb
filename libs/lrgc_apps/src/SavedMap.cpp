#include "lrgc_apps/SavedMap.h"

#include "lrgc_apps/ErrorText.h"

#include "lrgc_apps/io/LogReader.h"
#include "lrgc_apps/io/RawlogObjects.h"

#include <mrpt/maps/registerAllClasses.h>
#include <mrpt/obs/registerAllClasses.h>
#include <mrpt/serialization/CArchive.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace lrgc::apps
{
namespace
{
mrpt::maps::CSimpleMap readSimplemap(const std::string& file, const std::string& option)
{
	// Read as rawlogs are (RawlogObjects.h): the guard's child meets the object first, under
	// the memory budget, so a corrupted size cannot make this process allocate without bound
	// (13 GB before bad_alloc, issue 30) or crash in MRPT's deserializer.
	mrpt::obs::registerAllClasses_mrpt_obs();
	mrpt::maps::registerAllClasses_mrpt_maps();
	const auto unreadable = [&](const std::string& why) {
		return std::runtime_error(option + " '" + file + "': not a readable MRPT CSimpleMap (" +
								  why + ")");
	};
	std::shared_ptr<mrpt::maps::CSimpleMap> map;
	try
	{
		CLogInputFile in(file);
		TArchive archive(in);
		CDeserializationGuard guard(file);
		TObjectRead r = guard.checkNextObject(0);
		if (r.result != TObjectRead::Result::Failed) r = readArchiveObject(in, archive);
		if (r.result == TObjectRead::Result::Failed) throw unreadable(r.problem + " at " + r.place);
		if (r.result == TObjectRead::Result::End) throw unreadable("the file holds no object");
		map = std::dynamic_pointer_cast<mrpt::maps::CSimpleMap>(r.object);
		if (!map)
			throw unreadable(std::string("it holds a ") + r.object->GetRuntimeClass()->className);
	}
	catch (const CLogReadError& e)
	{
		throw unreadable(oneLineError(e));
	}
	if (map->empty())
		throw std::runtime_error(option + " '" + file + "': the map holds no keyframe");
	return std::move(*map);
}
}  // namespace

TSavedMap loadSavedMap(const std::string& path, const std::string& option)
{
	namespace fs = std::filesystem;
	std::error_code ec;
	TSavedMap out;
	out.path = path;
	if (!fs::exists(path, ec))
		throw std::runtime_error(
			option + " '" + path + "': no such file or folder; name an lrgc output folder or "
								   "a .simplemap(.gz) file");
	if (!fs::is_directory(path, ec))
	{
		out.keyframes = readSimplemap(path, option);
		return out;
	}
	const std::string simplemap = (fs::path(path) / kSimplemapFile).string();
	if (!fs::exists(simplemap, ec))
		throw std::runtime_error(
			option + " '" + path + "': the folder has no " + kSimplemapFile +
			" (is it an lrgc output folder?)");
	out.keyframes = readSimplemap(simplemap, option);
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
		throw std::runtime_error(
			option + " '" + path + "': " + kPoseGraphFile + " has " +
			std::to_string(out.graph->graph.numNodes()) + " nodes but " + kSimplemapFile +
			" " + std::to_string(out.keyframes.size()) +
			" keyframes: the files are of different runs");
	return out;
}

void initializeFromSavedMap(CMetricMapBuilderLRGC& builder, const TSavedMap& map)
{
	if (map.graph)
		builder.initialize(map.keyframes, map.graph->graph, map.graph->laserLabel);
	else
		builder.initialize(map.keyframes);
	if (builder.graph().numNodes() == 0)
		throw std::runtime_error(
			"'" + map.path + "': no keyframe of the map has a usable 2D laser scan");
}

}  // namespace lrgc::apps
