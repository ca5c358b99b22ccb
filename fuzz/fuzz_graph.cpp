/* Fuzz target: the graph.lrgc reader (poseGraphFromText), a saved map's pose graph.
 *
 * Invariants: it throws nothing but std::exception; a graph it accepts has every link between
 * two of its nodes and a positive-definite information matrix (addLink's checks), and written
 * back (poseGraphToText) it reads back to the same counts. */
#include <lrgc_apps/io/PoseGraphText.h>

#include <sstream>
#include <string>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
	lrgc::TSavedPoseGraph g;
	try
	{
		g = lrgc::poseGraphFromText(in, "fuzz.lrgc");
	}
	catch (const std::exception&)
	{
		return 0;
	}
	for (size_t id = 0; id < g.graph.numLinks(); ++id)
		LRGC_FUZZ_CHECK(g.graph.link(id).from < g.graph.numNodes() &&
							g.graph.link(id).to < g.graph.numNodes(),
						"links join nodes of the graph");
	std::istringstream again(lrgc::poseGraphToText(g.graph, g.laserLabel));
	try
	{
		const auto back = lrgc::poseGraphFromText(again, "again.lrgc");
		LRGC_FUZZ_CHECK(back.graph.numNodes() == g.graph.numNodes() &&
							back.graph.numLinks() == g.graph.numLinks(),
						"a graph read back has the same counts");
	}
	catch (const std::exception&)
	{
		LRGC_FUZZ_CHECK(false, "a graph it accepted, written back, is accepted");
	}
	return 0;
}
