/* lrgc-plot: one PNG per lrgc-slam run (map, trajectory, loop-closure links, per-scan
 * latency), for bench/run. All logic lives in lrgc::apps::eval::CPlotApp (libs/lrgc_apps). */
#include "eval/CPlotApp.h"

#include <iostream>
#include <string>
#include <vector>

int main(int argc, char** argv)
{
	const std::vector<std::string> args(argv + 1, argv + argc);
	return lrgc::apps::eval::CPlotApp::run(args, std::cout, std::cerr);
}
