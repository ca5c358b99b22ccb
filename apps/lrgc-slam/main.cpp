/* lrgc-slam: 2D laser SLAM (Local Registration and Global Correlation) for MRPT logs and live
 * mrpt::hwdrivers sensors. Everything lives in lrgc::apps::CSlamApp so tests can drive the
 * whole application; --live is handed to lrgc-slam-live (live_main.cpp), the same application
 * linked with the sensor drivers, which this program does not load (LiveProgram.h). */
#include "LiveProgram.h"
#include "SlamApp.h"

#include <string>
#include <vector>

int main(int argc, char** argv)
{
	const std::vector<std::string> args(argv + 1, argv + argc);
	return lrgc::apps::CSlamApp(stderr,
								[argv](const lrgc::apps::TSlamCommandLine&, std::FILE*) -> int
								{ lrgc::apps::execLiveProgram(argv); })
		.run(args);
}
