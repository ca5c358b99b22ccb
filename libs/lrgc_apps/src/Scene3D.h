/* map.3Dscene: the run's result as an mrpt::opengl::COpenGLScene, the format of MRPT's
 * SceneViewer3D (and of icp-slam's buildingmap_*.3Dscene), gzip-compressed. Objects, by name:
 *   "gridmap"     the occupancy grid (COccupancyGridMap2D::getVisualizationInto), z = 0
 *   "trajectory"  the robot's path, one segment per pair of consecutive scans, blue
 *   "keyframes"   the graph's nodes as points
 *   "loop_links"  the enabled LoopClosure links of the graph (stats.json's links.loop, as
 *                 lrgc-plot draws them), red, from node to node
 * The lines are lifted 5 cm above the grid so that they are not hidden in it. Written once,
 * at the end, with the other maps: never on the mapping path. */
#pragma once

#include <lrgc/map_builder/Trajectory.h>
#include <lrgc/pose_graph/PoseGraph.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/opengl/COpenGLScene.h>

#include <string>

namespace lrgc::apps
{
/** The scene (exposed for tests). */
mrpt::opengl::COpenGLScene makeScene3D(const mrpt::maps::COccupancyGridMap2D& grid,
									   const TTrajectory& trajectory, const CPoseGraph& graph);

/** Writes makeScene3D() to `path` (gzip archive), atomically. */
void writeScene3D(const mrpt::maps::COccupancyGridMap2D& grid, const TTrajectory& trajectory,
				  const CPoseGraph& graph, const std::string& path);

}  // namespace lrgc::apps
