/* A noisy laser (issue 28 items 2 and 5): MRPT's own synthetic logs, as Debian's mrpt-common
 * installs them, mapped by lrgc-slam with the defaults and scored against their exact ground
 * truth (ATE after the best-fit SE(2) alignment, eval/trajectory_error.h).
 *  - range_030_bearing_015.rawlog: range noise 0.30-0.33 m measured from its scans. Before
 *    the noise was estimated (RangeDenoiser.h), 96 scans failed the 0.1 m RMS gate, all 11
 *    loop searches failed the filters and the ATE rmse was 1.037 m, against MRPT's icp-slam's
 *    0.444 m (doc/benchmarks.md); 0.148 m with lines fitted through the points and the loop
 *    closed only at the end of the run; now 0.062 m, lines fitted along the rays, with 15
 *    online loop closures (ridge rivals, PatchCorrelator.h).
 *  - simul.rawlog, the same world with a quiet laser: its noise reads under the 0.1 m
 *    threshold, nothing is denoised and its map is as before (ATE rmse 0.047 m).
 * Skips where the datasets are absent. */
#include <gtest/gtest.h>
#include <lrgc_apps/eval/trajectory_error.h>

#include "app_runner.h"
#include "test_data.h"

#include <regex>

using namespace lrgc::test;
namespace eval = lrgc::apps::eval;

namespace
{
const std::string kDemos =
	"/usr/share/mrpt/datasets/graphslam-engine-demos/action_observations_map/";

double jsonNumber(const std::string& json, const std::string& key)
{
	std::smatch m;
	if (!std::regex_search(json, m, std::regex("\"" + key + "\": (-?[0-9.eE+-]+)"))) return -1;
	return std::stod(m[1]);
}

struct TMapped
{
	eval::TAbsoluteTrajectoryError ate;
	std::string stats;
};

/** The demo log `name` mapped with the defaults, scored against its .GT.txt. */
TMapped mapDemo(const std::string& name)
{
	const std::string dir = makeTempDir("noisy_" + name);
	const auto r = runProcess(binaryPath("lrgc-slam"),
							  {"--input", kDemos + name, "--out", dir + "/out", "--quiet"});
	EXPECT_EQ(r.exitCode, 0) << r.output;
	TMapped m;
	m.ate = eval::evaluateAte(eval::CTrajectory2D::loadFromFile(dir + "/out/trajectory.tum"),
							  eval::CTrajectory2D::loadFromFile(kDemos + name + ".GT.txt"));
	m.stats = readTextFile(dir + "/out/stats.json");
	std::cout << name << ": ATE rmse " << m.ate.trans_m.rms() << " m, range noise "
			  << jsonNumber(m.stats, "std_m") << " m, " << jsonNumber(m.stats, "scans_denoised")
			  << " scans denoised, " << jsonNumber(m.stats, "unmatched_scans")
			  << " unmatched, loop links " << jsonNumber(m.stats, "loop") << "\n";
	return m;
}
}  // namespace

TEST(NoisyLaser, mrptsRange030LogIsDenoisedAndMappedBetterThanIcpSlam)
{
	LRGC_SKIP_IF_MISSING(kDemos + "range_030_bearing_015.rawlog");
	const TMapped m = mapDemo("range_030_bearing_015.rawlog");
	const double noise = jsonNumber(m.stats, "std_m");
	EXPECT_GT(noise, 0.2);  // measured 0.29 at the end, 0.30-0.33 from the scans by hand
	EXPECT_LT(noise, 0.45);
	EXPECT_GT(jsonNumber(m.stats, "scans_denoised"), 1400);  // of 1460
	EXPECT_LT(m.ate.trans_m.rms(), 0.15);
	EXPECT_LT(
		jsonNumber(m.stats, "unmatched_scans"),
		20);  // 1 (142 with the TLS lines)  // icp-slam 0.444, 1.037, 0.148 before; now 0.062
	EXPECT_GT(jsonNumber(m.stats, "loop"), 0) << "the loop around the central block closed";
	EXPECT_GT(jsonNumber(m.stats, "loop_closures"), 0) << "closed online (15), not at the end";
}

TEST(NoisyLaser, aQuietLaserInTheSameWorldIsLeftAsItIs)
{
	LRGC_SKIP_IF_MISSING(kDemos + "simul.rawlog");
	const TMapped m = mapDemo("simul.rawlog");
	EXPECT_LT(jsonNumber(m.stats, "std_m"), 0.1);
	EXPECT_EQ(jsonNumber(m.stats, "scans_denoised"), 0);
	EXPECT_LT(m.ate.trans_m.rms(), 0.06);  // 0.047
}
