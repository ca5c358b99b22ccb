/* lrgc-slam: 2D laser SLAM (Local Registration and Global Correlation) for MRPT logs.
 * Everything lives in lrgc::apps::CSlamApp so tests can drive the whole application. */
#include <lrgc_apps/SlamApp.h>

#include <string>
#include <vector>

int main(int argc, char** argv)
{
	const std::vector<std::string> args(argv + 1, argv + argc);
	return lrgc::apps::CSlamApp().run(args);
}
