/* End to end: which laser lrgc-slam maps (issue 14, item 3). A log with two lasers maps the
 * first one seen unless --laser (or [MapBuilder] laser_label) names another; the default run
 * warns once, naming both lasers and the option, and stats.json counts the scans ignored per
 * laser. One CARMEN RLASER line in front of the FLASER lines used to map 1 scan and drop every
 * other in silence.
 *   - a synthetic CARMEN log (a room, a front and a rear laser) generated here: always runs;
 *   - Intel's first 3000 lines with one RLASER line (a copy of its first FLASER line) in
 *     front, generated from the shared log at test time: skips where the log is absent. */
#include <gtest/gtest.h>

#include <lrgc/common/se2.h>

#include <regex>
#include <sstream>

#include "app_runner.h"
#include "io_test_files.h"
#include "synthetic_world.h"
#include "test_data.h"

using namespace lrgc::test;
using mrpt::math::TPose2D;

namespace
{
/** The whole number after `"key": ` in stats.json (-1 if absent). */
long statsCount(const std::string& stats, const std::string& key)
{
	std::smatch m;
	if (!std::regex_search(stats, m, std::regex("\"" + key + "\": ([0-9]+)"))) return -1;
	return std::stol(m[1]);
}

size_t countOfLaser(const std::string& text, const std::string& what)
{
	size_t n = 0;
	for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1))
		++n;
	return n;
}

/** 181 readings, 1 degree apart, of the laser at `laserInWorld` (50 m: no return). */
std::vector<double> castScan(const CSyntheticWorld& world, const TPose2D& laserInWorld)
{
	std::vector<double> r;
	for (int i = 0; i <= 180; ++i)
		r.push_back(world
						.castRay({laserInWorld.x, laserInWorld.y},
								 laserInWorld.phi + mrpt::DEG2RAD(double(i - 90)), 50.0)
						.value_or(50.0));
	return r;
}

/** A room driven through by a robot with a front laser (FLASER) and a rear one (RLASER,
 * turned by 180 deg, 0.2 m behind); the rear laser fires once, before the first front scan. */
std::string twoLaserLog(size_t* frontScans)
{
	const CSyntheticWorld world = makeRoomWorld(5, 4);
	const TTrajectory tr = makeTrajectory({{1.5, 3.5}, {5.5, 3.5}, {5.5, 5.8}, {2.0, 5.8}}, 0.1,
										  TOdometryNoise{}, 21);
	const TPose2D rearInRobot(-0.2, 0, M_PI);
	std::string log;
	const auto rearOdo = lrgc::compose(tr.odometryPoses[0], rearInRobot);
	log += flaserLine(castScan(world, lrgc::compose(tr.truePoses[0], rearInRobot)), rearOdo,
					  tr.odometryPoses[0], 99.95, "RLASER");
	for (size_t k = 0; k < tr.truePoses.size(); ++k)
		log += flaserLine(castScan(world, tr.truePoses[k]), tr.odometryPoses[k],
						  tr.odometryPoses[k], 100.0 + 0.2 * double(k));
	*frontScans = tr.truePoses.size();
	return log;
}

struct TLaserChoiceRun
{
	int exitCode;
	std::string output, stats;
};

TLaserChoiceRun runSlam(const std::string& log, const std::string& out,
						std::vector<std::string> extra = {})
{
	std::vector<std::string> args{"--input", log, "--out", out, "--quiet"};
	args.insert(args.end(), extra.begin(), extra.end());
	const auto r = runProcess(binaryPath("lrgc-slam"), args);
	return {r.exitCode, r.output, readTextFile(out + "/stats.json")};
}

/** The default run maps the rear laser's one scan and says so; --laser LASER maps every front
 * scan; a label the log lacks maps nothing and names the lasers it has. */
void checkLaserChoice(const std::string& log, size_t frontScans, const std::string& dir)
{
	const TLaserChoiceRun byDefault = runSlam(log, dir + "/default");
	EXPECT_EQ(byDefault.exitCode, 0) << byDefault.output;
	EXPECT_EQ(countOfLaser(byDefault.output, "a second laser"), 1u) << byDefault.output;
	EXPECT_NE(byDefault.output.find("warning: a second laser: mapping 'REAR_LASER' (the first "
									"seen), ignoring the scans of 'LASER'"),
			  std::string::npos)
		<< byDefault.output;
	EXPECT_NE(byDefault.output.find("--laser LASER"), std::string::npos) << byDefault.output;
	EXPECT_EQ(statsCount(byDefault.stats, "scans"), 1) << byDefault.stats;
	EXPECT_NE(byDefault.stats.find("\"laser\": {\"label\": \"REAR_LASER\", \"chosen\": false, "
								   "\"ignored_scans\": {\"LASER\": " +
								   std::to_string(frontScans) + "}"),
			  std::string::npos)
		<< byDefault.stats;

	const TLaserChoiceRun front = runSlam(log, dir + "/front", {"--laser", "LASER"});
	EXPECT_EQ(front.exitCode, 0) << front.output;
	EXPECT_EQ(front.output.find("second laser"), std::string::npos) << front.output;
	EXPECT_EQ(statsCount(front.stats, "scans"), long(frontScans)) << front.stats;
	EXPECT_EQ(statsCount(front.stats, "skipped_scans"), 0) << front.stats;
	EXPECT_NE(front.stats.find("\"laser\": {\"label\": \"LASER\", \"chosen\": true, "
							   "\"ignored_scans\": {\"REAR_LASER\": 1}"),
			  std::string::npos)
		<< front.stats;
	EXPECT_EQ(countOfLaser(readTextFile(dir + "/front/trajectory.tum"), "\n"), frontScans);

	// The same choice from the .ini.
	writeTextFile(dir + "/front.ini", "[MapBuilder]\nlaser_label = LASER\n");
	const TLaserChoiceRun fromIni =
		runSlam(log, dir + "/front-ini", {"--config", dir + "/front.ini"});
	EXPECT_EQ(fromIni.exitCode, 0) << fromIni.output;
	EXPECT_EQ(statsCount(fromIni.stats, "scans"), long(frontScans)) << fromIni.stats;

	const TLaserChoiceRun none = runSlam(log, dir + "/none", {"--laser", "TOP_LASER"});
	EXPECT_EQ(none.exitCode, 1) << none.output;
	EXPECT_NE(none.output.find("has no scan of laser 'TOP_LASER' (--laser, [MapBuilder] "
							   "laser_label); its lasers: LASER (" +
							   std::to_string(frontScans) + " scans), REAR_LASER (1 scan)"),
			  std::string::npos)
		<< none.output;
}
}  // namespace

TEST(LaserChoice, SyntheticTwoLaserLog)
{
	const std::string dir = makeTempDir("laser_choice_synthetic");
	size_t frontScans = 0;
	writeTextFile(dir + "/two-lasers.clf", twoLaserLog(&frontScans));
	ASSERT_GT(frontScans, 50u);
	checkLaserChoice(dir + "/two-lasers.clf", frontScans, dir);

	// --laser is for mapping: without a value, or with a conversion only, a usage error.
	const auto noValue = runProcess(
		binaryPath("lrgc-slam"), {"--input", dir + "/two-lasers.clf", "--out", dir, "--laser"});
	EXPECT_EQ(noValue.exitCode, 2) << noValue.output;
	EXPECT_NE(noValue.output.find("option --laser needs a value"), std::string::npos)
		<< noValue.output;
	const auto convert = runProcess(binaryPath("lrgc-slam"),
									{"--input", dir + "/two-lasers.clf", "--save-rawlog",
									 dir + "/two.rawlog", "--laser", "LASER"});
	EXPECT_EQ(convert.exitCode, 2) << convert.output;
	EXPECT_NE(convert.output.find("--laser picks the laser to map"), std::string::npos)
		<< convert.output;
}

TEST(LaserChoice, IntelWithOneRearLaserLineInFront)
{
	const std::string intel = sharedDatasetPath("intel/intel.clf.gz");
	LRGC_SKIP_IF_MISSING(intel);
	std::istringstream in(readUncompressed(intel));
	std::string line, head, firstFront;
	size_t frontScans = 0;
	for (int i = 0; i < 3000 && std::getline(in, line); ++i)
	{
		head += line + "\n";
		if (line.rfind("FLASER ", 0) != 0) continue;
		++frontScans;
		if (firstFront.empty()) firstFront = line;
	}
	ASSERT_GT(frontScans, 500u);
	const std::string dir = makeTempDir("laser_choice_intel");
	writeTextFile(dir + "/intel-3000.clf", "R" + firstFront.substr(1) + "\n" + head);
	checkLaserChoice(dir + "/intel-3000.clf", frontScans, dir);
}
