/* A saved map for --initial-map and --localize: an earlier lrgc output folder, or any MRPT
 * .simplemap(.gz) (icp-slam's _finalmap_.simplemap, ...).
 *
 * A folder gives map.simplemap.gz (the keyframes, node i = entry i) and graph.lrgc (the whole
 * pose graph, link types and disabled links included: PoseGraphText.h), so the map is
 * continued exactly; a folder of an lrgc without graph.lrgc, or a .simplemap file, gives the
 * keyframes and their poses only (CMetricMapBuilderLRGC::initialize links them anew). */
#pragma once

#include <lrgc_apps/io/PoseGraphText.h>
#include <lrgc/map_builder/CMetricMapBuilderLRGC.h>
#include <mrpt/maps/CSimpleMap.h>

#include <optional>
#include <string>
#include <vector>

namespace lrgc::apps
{
/** File names in an output folder. */
constexpr const char* kSimplemapFile = "map.simplemap.gz";
constexpr const char* kPoseGraphFile = "graph.lrgc";

struct TSavedMap
{
	std::string path;
	mrpt::maps::CSimpleMap keyframes;
	std::optional<TSavedPoseGraph> graph;  //!< from graph.lrgc, if the folder has one
	std::vector<std::string> warnings;     //!< for the user (graph->warning)
};

/** Loads `path` (a folder or a simplemap file); `option` names the command-line option in
 * errors. Throws std::runtime_error with a one-line message naming the file and the problem
 * (missing, unreadable, not a simplemap, empty, graph of another map). */
TSavedMap loadSavedMap(const std::string& path, const std::string& option);

/** builder.initialize() with the saved map: exactly (graph.lrgc) or from the keyframes. */
void initializeFromSavedMap(CMetricMapBuilderLRGC& builder, const TSavedMap& map);

}  // namespace lrgc::apps
