/* lrgc-slam: 2D laser SLAM (Local Registration and Global Correlation) for MRPT logs and live
 * mrpt::hwdrivers sensors. Everything lives in lrgc::apps::CSlamApp (and, for --live, in
 * lrgc::apps::runLiveSlam) so tests can drive the whole application. */
#include "SlamApp.h"
#include "live/LiveSlam.h"

#include <string>
#include <vector>

int main(int argc, char** argv)
{
	const std::vector<std::string> args(argv + 1, argv + argc);
	return lrgc::apps::CSlamApp(stderr, lrgc::apps::runLiveSlam).run(args);
}
