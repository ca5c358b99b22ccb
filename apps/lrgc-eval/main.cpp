/* lrgc-eval: relation error (Kuemmerle et al. 2009) and ATE/RPE of a 2D trajectory.
 * All logic lives in lrgc::apps::eval::CEvalApp (libs/lrgc_apps), so tests can call it. */
#include "eval/CEvalApp.h"

#include <iostream>
#include <string>
#include <vector>

int main(int argc, char** argv)
{
	const std::vector<std::string> args(argv + 1, argv + argc);
	return lrgc::apps::eval::CEvalApp::run(args, std::cout, std::cerr);
}
