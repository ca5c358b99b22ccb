/* Writers of lrgc-slam's outputs. Every one writes atomically (temporary file + rename), so a
 * reader, or a run killed mid-write, never sees a partial file.
 *
 *  map.gridmap.gz    COccupancyGridMap2D in an MRPT archive (gzip): pf-localization's map
 *  map.png           the same grid as an image (white free, black occupied, grey unknown)
 *  map.pgm/map.yaml  ROS map_server convention (origin = lower-left cell corner, metres)
 *  map.simplemap.gz  CSimpleMap of keyframes (pose + sensory frame)
 *  trajectory.tum    "t x y z qx qy qz qw", one line per scan, t = the scan's own timestamp
 *  graph.graph       MRPT/g2o text (VERTEX_SE2, EDGE_SE2)
 *  graph.lrgc        the whole graph for --initial-map (lrgc_apps/io/PoseGraphText.h)
 */
#pragma once

#include <lrgc/map_builder/Trajectory.h>
#include <mrpt/graphs/CNetworkOfPoses.h>

#include <string>

namespace mrpt::maps
{
class COccupancyGridMap2D;
class CSimpleMap;
}  // namespace mrpt::maps

namespace lrgc::apps
{
void writeGridmap(const mrpt::maps::COccupancyGridMap2D& grid, const std::string& path);
void writeGridPng(const mrpt::maps::COccupancyGridMap2D& grid, const std::string& path);
/** Writes `<stem>.pgm` and `<stem>.yaml` (the yaml names the pgm by its file name). */
void writeRosMap(const mrpt::maps::COccupancyGridMap2D& grid, const std::string& stemPath);
void writeSimplemap(const mrpt::maps::CSimpleMap& map, const std::string& path);
/** TUM rows (stamp x y z qx qy qz qw) of the poses, one a line. */
std::string trajectoryTumText(const TTrajectory& trajectory);
void writeTrajectoryTum(const TTrajectory& trajectory, const std::string& path);
void writeGraph(const mrpt::graphs::CNetworkOfPoses2DInf& graph, const std::string& path);

}  // namespace lrgc::apps
