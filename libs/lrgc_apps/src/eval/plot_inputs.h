/* Readers for the outputs of lrgc-slam that lrgc-plot draws: the ROS map_server map
 * (map.yaml + map.pgm), the pose graph (graph.graph, VERTEX_SE2 / EDGE_SE2 lines as written by
 * mrpt::graphs::CNetworkOfPoses2DInf::saveToTextFile), and the per-scan timing
 * (timing.csv: `scan_index,timestamp,latency_ms`). Malformed lines throw "file:line: ...".
 */
#pragma once

#include <mrpt/math/TPose2D.h>

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace lrgc::apps::eval
{
/** The keys of a ROS map_server YAML file that matter for drawing. */
struct TRosMapInfo
{
	std::string imagePath;  //!< resolved against the YAML file's folder
	double resolution = 0;  //!< [m/pixel]
	/** Pose of the lower-left pixel's corner in the world: x [m], y [m], yaw [rad]. */
	mrpt::math::TPose2D origin;
	bool negate = false;
};

/** Reads `image`, `resolution`, `origin: [x, y, yaw]` and `negate` (other keys ignored).
 * Throws naming the file (and line) if a required key is missing or malformed. */
TRosMapInfo loadRosMapYaml(const std::string& path);

struct TGraphFile
{
	std::map<std::size_t, mrpt::math::TPose2D> vertices;     //!< id -> (map <- keyframe)
	std::vector<std::pair<std::size_t, std::size_t>> edges;  //!< (from, to) ids
	/** graph.lrgc only: its enabled links of type LoopClosure, the "loop links" that
	 * stats.json counts as links.loop. Empty optional for a graph.graph (no link types). */
	std::optional<std::vector<std::pair<std::size_t, std::size_t>>> loopLinks;
	std::string warning;  //!< graph.lrgc only: TSavedPoseGraph::warning
};

/** Reads an lrgc graph.lrgc (first record LRGC_POSE_GRAPH: nodes, typed links; disabled
 * links are left out) or a graph.graph (VERTEX_SE2 and EDGE_SE2 lines; other keywords such as
 * FIX and '#' comments are skipped). Throws "file:line: ..." on a malformed line. */
TGraphFile loadGraphFile(const std::string& path);

/** The loop links to draw: a graph.lrgc's LoopClosure links (the same count as stats.json's
 * links.loop); for a graph.graph, which has no link types, the edges whose vertex ids are
 * more than `minIdGap` apart (local registration links each keyframe to the last K
 * keyframes only, but a K-window scan-match link can span more ids than the gap, so this
 * over-counts: give graph.lrgc). */
std::vector<std::pair<std::size_t, std::size_t>> loopClosureEdges(const TGraphFile& graph,
																  std::size_t minIdGap);

struct TScanTiming
{
	std::size_t scanIndex = 0;
	double timestamp = 0;   //!< [s]
	double latency_ms = 0;  //!< [ms]
};

/** Reads timing.csv (header line, then `scan_index,timestamp,latency_ms`, and in a
 * --localize run's `replay_wait_ms,cpu_ms` after them, not read). */
std::vector<TScanTiming> loadTimingCsv(const std::string& path);

}  // namespace lrgc::apps::eval
