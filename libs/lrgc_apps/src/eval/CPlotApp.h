/* lrgc-plot as a library class: one PNG per run of lrgc-slam, for doc/benchmarks.md.
 *
 * Top panel: the occupancy map (map.yaml + map.pgm), cropped to its known cells and the
 * trajectory, with the trajectory (trajectory.tum, blue), its start (green) and end (black
 * dot), the loop-closure links of the pose graph (graph.graph, red: edges between keyframes
 * more than `loopMinGap` ids apart) and a scale bar. Bottom panel: per-scan latency
 * (timing.csv) against scan index, log-scaled, with its median and 99th percentile.
 *
 *   lrgc-plot --map map.yaml --trajectory trajectory.tum [--graph graph.graph]
 *             [--timing timing.csv] [--title TEXT] [--loop-min-gap N] --out plot.png
 */
#pragma once

#include <cstddef>
#include <iosfwd>
#include <string>
#include <vector>

namespace lrgc::apps::eval
{
struct TPlotOptions
{
	std::string mapYaml, trajectory, graph, timing, out, title;
	std::size_t loopMinGap =
		15;                   //!< edges with a larger id gap are loop-closure links (window K)
	int width = 1200;         //!< [pixels] of the output image
	int maxMapHeight = 1000;  //!< [pixels] of the map panel at most
};

/** What was drawn, and where: world point (x, y) [m] lands on output pixel
 * (col, row) = (mapOriginCol + pixelsPerMetre * x, mapOriginRow - pixelsPerMetre * y)
 * for a map whose origin yaw is 0. */
struct TPlotSummary
{
	int width = 0, height = 0;  //!< [pixels] of the PNG
	std::size_t trajectoryPoses = 0, loopLinks = 0, timedScans = 0;
	double pixelsPerMetre = 0;
	double mapOriginCol = 0, mapOriginRow = 0;
	int mapPanelTop = 0, mapPanelHeight = 0;  //!< rows of the map panel in the PNG
	std::string warning;                      //!< about an input (TGraphFile::warning)
};

class CPlotApp
{
public:
	/** Throws std::invalid_argument for unknown options, missing values or inputs. */
	static TPlotOptions parseArguments(const std::vector<std::string>& args);
	static std::string usage();
	/** Reads the inputs, draws, and writes options.out (atomically). Throws MRPT exceptions
	 * naming the file (and line) on unreadable or malformed inputs. */
	static TPlotSummary render(const TPlotOptions& options);
	/** The CLI: 0 on success, 1 on input errors, 2 on usage errors (messages to err). */
	static int run(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
};

}  // namespace lrgc::apps::eval
