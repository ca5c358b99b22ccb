#include "Scene3D.h"

#include "atomic_file.h"

#include <mrpt/opengl/CPointCloud.h>
#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/serialization/CArchive.h>

namespace lrgc::apps
{
namespace
{
constexpr float kLift = 0.05f;  // [m] lines above the grid plane

mrpt::opengl::CSetOfLines::Ptr lines(const std::string& name, const mrpt::img::TColorf& color,
									 float width)
{
	auto l = mrpt::opengl::CSetOfLines::Create();
	l->setName(name);
	l->setColor(color);
	l->setLineWidth(width);
	return l;
}
}  // namespace

mrpt::opengl::COpenGLScene makeScene3D(const mrpt::maps::COccupancyGridMap2D& grid,
									   const TTrajectory& trajectory, const CPoseGraph& graph)
{
	mrpt::opengl::COpenGLScene scene;
	auto gridObj = mrpt::opengl::CSetOfObjects::Create();
	grid.getVisualizationInto(*gridObj);
	gridObj->setName("gridmap");
	scene.insert(gridObj);

	auto path = lines("trajectory", {0.f, 0.f, 1.f}, 2.f);
	for (size_t i = 1; i < trajectory.size(); ++i)
	{
		const auto& a = trajectory[i - 1].robotInMap;
		const auto& b = trajectory[i].robotInMap;
		path->appendLine(a.x, a.y, kLift, b.x, b.y, kLift);
	}
	scene.insert(path);

	auto nodes = mrpt::opengl::CPointCloud::Create();
	nodes->setName("keyframes");
	nodes->setPointSize(4.f);
	nodes->setColor(0.f, 0.5f, 0.f);
	for (size_t i = 0; i < graph.numNodes(); ++i)
		nodes->insertPoint(static_cast<float>(graph.pose(i).x),
						   static_cast<float>(graph.pose(i).y), kLift);
	scene.insert(nodes);

	auto loops = lines("loop_links", {1.f, 0.f, 0.f}, 2.f);
	for (size_t id = 0; id < graph.numLinks(); ++id)
	{
		const TLink& l = graph.link(id);
		if (l.type != LinkType::LoopClosure || !graph.isLinkEnabled(id)) continue;
		const auto& a = graph.pose(l.from);
		const auto& b = graph.pose(l.to);
		loops->appendLine(a.x, a.y, kLift, b.x, b.y, kLift);
	}
	scene.insert(loops);
	return scene;
}

void writeScene3D(const mrpt::maps::COccupancyGridMap2D& grid, const TTrajectory& trajectory,
				  const CPoseGraph& graph, const std::string& path)
{
	const mrpt::opengl::COpenGLScene scene = makeScene3D(grid, trajectory, graph);
	// Gzip as MRPT's CFileGZOutputStream writes it (SceneViewer3D reads either), every write
	// checked: a full disk never publishes a cut scene.
	writeArchiveAtomically(path, TFileCompression::Gzip,
						   [&](mrpt::serialization::CArchive& a) { a << scene; });
}

}  // namespace lrgc::apps
