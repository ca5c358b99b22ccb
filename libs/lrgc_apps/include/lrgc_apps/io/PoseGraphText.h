/* The whole pose graph as text, so that a saved map can be continued exactly (lrgc-slam
 * --initial-map): every node pose, every link with its measurement, information, type and
 * whether it is enabled, in full precision (%.17g, so a round trip is bit-exact).
 *
 * MRPT's .graph (graph.graph) cannot serve: it keeps neither link types (the optimizer makes
 * only LoopClosure links robust) nor disabled links, and g2o readers want one edge per pair.
 *
 * Format (one record per line, '#' comments):
 *   LRGC_POSE_GRAPH 3
 *   LASER <sensor label of the keyframes' scans>          (optional)
 *   NODE <i> <x> <y> <phi> <session>                       (i = 0, 1, 2, ... in order)
 *   LINK <from> <to> <x> <y> <phi> <I00> <I01> <I02> <I11> <I12> <I22> <type> <enabled>
 *   END <nodes> <links>                                    (last; version 1 files lack it)
 * Units m and rad; Z = (from <- to); I the upper triangle of the information matrix over
 * (x, y, phi) in the frame of `from`; type Odometry | ScanMatch | LoopClosure; enabled 0 | 1.
 * Node i is entry i of the map's CSimpleMap (map.simplemap.gz); its session is the mapping
 * session whose scan that entry holds (TKeyframe::session: 0 the first, each continuation
 * one more), so a map continued again still shows each place as its newest session saw it.
 * Versions 1 and 2 (NODE without the session) are still read, every node as session 0.
 */
#pragma once

#include <lrgc/pose_graph/PoseGraph.h>

#include <istream>
#include <string>
#include <vector>

namespace lrgc
{
struct TSavedPoseGraph
{
	CPoseGraph graph;
	std::string laserLabel;        //!< empty if the file names none
	std::vector<size_t> sessions;  //!< per node (TKeyframe::session); all 0 before version 3
	/** One line for the user when the file cannot be checked whole (a version 1 file, which
	 * has no END line), else empty. */
	std::string warning;
};

/** `sessions`: per node (TKeyframe::session); empty: all 0. */
std::string poseGraphToText(const CPoseGraph& graph, const std::string& laserLabel = {},
							const std::vector<size_t>& sessions = {});

/** Parses the text written by poseGraphToText(); throws naming `where` and the line number
 * on anything else (unknown record, bad number, node out of order, invalid link, a last line
 * without its newline; in a version 2 file, no END line or counts other than its own: a file
 * cut at a line boundary). A version 1 file loads with a `warning`. */
TSavedPoseGraph poseGraphFromText(std::istream& in, const std::string& where);

}  // namespace lrgc
