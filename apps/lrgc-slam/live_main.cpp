/* lrgc-slam-live: lrgc-slam linked with the live sensor drivers (mrpt::hwdrivers), which
 * lrgc-slam execs for --live (LiveProgram.h); everything else as lrgc-slam. Installed beside
 * the programs' private files (libexec/lrgc), not on the PATH. */
#include "SlamApp.h"
#include "live/LiveSlam.h"

#include <string>
#include <vector>

int main(int argc, char** argv)
{
	const std::vector<std::string> args(argv + 1, argv + argc);
	return lrgc::apps::CSlamApp(stderr, lrgc::apps::runLiveSlam).run(args);
}
