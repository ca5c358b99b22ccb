/* Our map is usable by MRPT's own clients: lrgc-slam maps the SENA rawlog (Debian
 * mrpt-common), then MRPT's real `pf-localization` (Debian mrpt-apps) localises the same log
 * on our map.gridmap.gz with 2000 particles started around the first pose. Its estimated path
 * (the "PDF estimation" it logs at each step; with 3DSceneFrequency = -1 it writes no
 * per-step pose file) must follow our trajectory.tum for most of the run, while the log's own
 * odometry ends metres away: only a right map keeps the filter there.
 *
 * Tolerances (measured: median 0.11 m, 98 % of steps within 0.3 m, worst 0.41 m, heading
 * within 5.5 deg; the filter's random draws are not seeded by pf-localization):
 * at least 90 % of the steps within 0.3 m and 5 deg, median below 0.2 m, every step within
 * 1 m, the last pose within 0.5 m. */
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "app_runner.h"
#include "test_data.h"

namespace fs = std::filesystem;
using namespace lrgc::test;

namespace
{
const char* kPfLocalization = "/usr/bin/pf-localization";

struct TPose
{
	double x = 0, y = 0, phi = 0;  // [m, m, rad]
};

/** Timestamps [s] of the laser scan of each action/observation pair, in file order: the
 * steps pf-localization runs (it skips a leading sensory frame without an action). */
std::vector<double> pairScanTimes(const std::string& rawlog)
{
	mrpt::io::CFileGZInputStream f(rawlog);
	auto arch = mrpt::serialization::archiveFrom(f);
	std::vector<double> times;
	mrpt::obs::CActionCollection::Ptr action;
	mrpt::obs::CSensoryFrame::Ptr sf;
	mrpt::obs::CObservation::Ptr obs;
	size_t index = 0;
	while (
		mrpt::obs::CRawlog::getActionObservationPairOrObservation(arch, action, sf, obs, index))
	{
		if (!action || !sf) continue;
		const auto laser = sf->getObservationByClass<mrpt::obs::CObservation2DRangeScan>();
		if (laser) times.push_back(mrpt::Clock::toDouble(laser->timestamp));
	}
	return times;
}

/** trajectory.tum: "t x y z qx qy qz qw" -> (t, pose). */
std::vector<std::pair<double, TPose>> readTum(const std::string& path)
{
	std::ifstream f(path);
	std::vector<std::pair<double, TPose>> out;
	double t, x, y, z, qx, qy, qz, qw;
	while (f >> t >> x >> y >> z >> qx >> qy >> qz >> qw)
		out.push_back({t, {x, y, 2 * std::atan2(qz, qw)}});
	return out;
}

/** The poses pf-localization logs as "<label>: (x,y,phi_deg)", in step order. */
std::vector<TPose> loggedPoses(const std::string& log, const std::string& label)
{
	const std::regex re(label + R"(: \(([-0-9.]+),([-0-9.]+),([-0-9.]+)deg\))");
	std::vector<TPose> out;
	for (auto it = std::sregex_iterator(log.begin(), log.end(), re);
		 it != std::sregex_iterator(); ++it)
		out.push_back(
			{std::stod((*it)[1]), std::stod((*it)[2]), std::stod((*it)[3]) * M_PI / 180});
	return out;
}

std::string pfConfig(const std::string& map, const std::string& rawlog,
					 const std::string& logDir)
{
	std::ostringstream s;
	s << "[KLD_options]\nKLD_binSize_PHI_deg=10\nKLD_binSize_XY=0.10\nKLD_delta=0.01\n"
		 "KLD_epsilon=0.01\nKLD_maxSampleSize=4000\nKLD_minSampleSize=150\nKLD_"
		 "minSamplesPerBin=0\n"
		 "\n[PF_options]\nPF_algorithm=0\nresamplingMethod=0\nadaptiveSampleSize=1\nBETA=0.5\n"
		 "sampleSize=1\npfAuxFilterOptimal_MaximumSearchSamples=10\n"
		 "\n[LocalizationExperiment]\nuse_3D_poses=false\n"
	  << "map_file=" << map << "\nrawlog_file=" << rawlog << "\nlogOutput_dir=" << logDir
	  << "\n"
	  << "3DSceneFrequency=-1\nSHOW_PROGRESS_3D_REAL_TIME=false\nexperimentRepetitions=1\n"
		 "particles_count=2000\n"
		 // Uniform over +-0.5 m and +-10 deg around our map's origin, the first pose.
		 "init_PDF_mode=1\ninit_PDF_min_x=-0.5\ninit_PDF_max_x=0.5\ninit_PDF_min_y=-0.5\n"
		 "init_PDF_max_y=0.5\ninit_PDF_min_yaw_deg=-10\ninit_PDF_max_yaw_deg=10\n"
		 "\n[MetricMap]\noccupancyGrid_count=1\nlikelihoodMapSelection=-1\n"
		 "\n[MetricMap_occupancyGrid_00_creationOpts]\nresolution=0.05\n"
		 "\n[MetricMap_occupancyGrid_00_insertOpts]\nmaxDistanceInsertion=15\n"
		 "\n[MetricMap_occupancyGrid_00_likelihoodOpts]\nlikelihoodMethod=4\nLF_decimation=5\n"
		 "LF_stdHit=0.20\nLF_maxCorrsDistance=0.30\nLF_zHit=0.95\nLF_zRandom=0.05\n"
		 "LF_maxRange=80\nLF_alternateAverageMethod=0\n";
	return s.str();
}

double headingError(const TPose& a, const TPose& b)
{
	return std::abs(mrpt::math::wrapToPi(a.phi - b.phi));
}
double positionError(const TPose& a, const TPose& b)
{
	return std::hypot(a.x - b.x, a.y - b.y);
}
}  // namespace

TEST(PfLocalization, localisesTheSenaLogOnOurMapAlongOurTrajectory)
{
	LRGC_SKIP_IF_MISSING(senaRawlogPath());
	if (!fileExists(kPfLocalization))
		GTEST_SKIP() << kPfLocalization << " not installed (Debian package mrpt-apps)";
	// CTest runs test processes in parallel: one directory per process.
	const std::string dir = makeTempDir("pf_localization_" + std::to_string(::getpid()));
	const std::string slamOut = dir + "/slam";
	const auto slam = runProcess(binaryPath("lrgc-slam"),
								 {"--input", senaRawlogPath(), "--out", slamOut, "--quiet"});
	ASSERT_EQ(slam.exitCode, 0) << slam.output;

	writeTextFile(dir + "/pf.ini",
				  pfConfig(slamOut + "/map.gridmap.gz", senaRawlogPath(), dir + "/LOG"));
	const auto pf = runProcess(kPfLocalization, {dir + "/pf.ini"}, dir);
	writeTextFile(dir + "/pf-localization.log", pf.output);
	ASSERT_EQ(pf.exitCode, 0) << "pf-localization failed, log in " << dir << ":\n"
							  << pf.output.substr(
									 pf.output.size() > 3000 ? pf.output.size() - 3000 : 0);

	const std::vector<TPose> estimate = loggedPoses(pf.output, "PDF estimation");
	const std::vector<TPose> odometry = loggedPoses(pf.output, "Odometry estimation");
	const std::vector<double> stepTimes = pairScanTimes(senaRawlogPath());
	ASSERT_EQ(stepTimes.size(), 224U);
	ASSERT_EQ(estimate.size(), stepTimes.size()) << "one estimate per step, log in " << dir;
	ASSERT_EQ(odometry.size(), stepTimes.size());

	// Our pose at each step: the trajectory line with the step's scan timestamp.
	const auto ours = readTum(slamOut + "/trajectory.tum");
	std::vector<double> errXY;
	size_t good = 0;
	TPose lastOurs;
	for (size_t k = 0; k < stepTimes.size(); ++k)
	{
		const auto it = std::find_if(ours.begin(), ours.end(),
									 [&](const auto& tp)
									 { return std::abs(tp.first - stepTimes[k]) < 1e-4; });
		ASSERT_NE(it, ours.end()) << "no trajectory.tum line at t = " << stepTimes[k];
		const double dxy = positionError(estimate[k], it->second);
		errXY.push_back(dxy);
		good += dxy <= 0.3 && headingError(estimate[k], it->second) <= 5 * M_PI / 180;
		EXPECT_LT(dxy, 1.0) << "step " << k;
		lastOurs = it->second;
	}
	const double fractionGood = double(good) / double(stepTimes.size());
	std::vector<double> sorted = errXY;
	std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
	const double median = sorted[sorted.size() / 2];
	RecordProperty("fraction_within_0.3m_5deg", std::to_string(fractionGood));
	RecordProperty("median_error_m", std::to_string(median));
	EXPECT_GE(fractionGood, 0.9);
	EXPECT_LT(median, 0.2);
	EXPECT_LT(positionError(estimate.back(), lastOurs), 0.5);
	// The log's odometry alone ends metres away: the filter followed the map, not odometry.
	EXPECT_GT(positionError(odometry.back(), lastOurs), 3.0);
}

// The pf-localization.ini lrgc-slam writes into its output folder runs as it is, from another
// folder, headless, and converges: median position error <= 0.15 m against trajectory.tum.
TEST(PfLocalization, theOutputFoldersIniRunsAsItIs)
{
	LRGC_SKIP_IF_MISSING(senaRawlogPath());
	if (!fileExists(kPfLocalization))
		GTEST_SKIP() << kPfLocalization << " not installed (Debian package mrpt-apps)";
	const std::string dir = makeTempDir("pf_ini_" + std::to_string(::getpid()));
	const std::string out = dir + "/out";
	const auto slam = runProcess(binaryPath("lrgc-slam"),
								 {"--input", senaRawlogPath(), "--out", out, "--quiet"});
	ASSERT_EQ(slam.exitCode, 0) << slam.output;
	fs::create_directories(dir + "/elsewhere");
	const std::string gridBefore = readTextFile(out + "/map.gridmap.gz");
	const auto pf =
		runProcess(kPfLocalization, {out + "/pf-localization.ini"}, dir + "/elsewhere");
	writeTextFile(dir + "/pf-localization.log", pf.output);
	ASSERT_EQ(pf.exitCode, 0) << "log in " << dir;

	const std::vector<TPose> estimate = loggedPoses(pf.output, "PDF estimation");
	const std::vector<double> stepTimes = pairScanTimes(senaRawlogPath());
	ASSERT_EQ(estimate.size(), stepTimes.size()) << "one estimate per step, log in " << dir;
	const auto ours = readTum(out + "/trajectory.tum");
	std::vector<double> errXY;
	for (size_t k = 0; k < stepTimes.size(); ++k)
	{
		const auto it = std::find_if(ours.begin(), ours.end(),
									 [&](const auto& tp)
									 { return std::abs(tp.first - stepTimes[k]) < 1e-4; });
		ASSERT_NE(it, ours.end()) << "no trajectory.tum line at t = " << stepTimes[k];
		errXY.push_back(positionError(estimate[k], it->second));
	}
	std::nth_element(errXY.begin(), errXY.begin() + errXY.size() / 2, errXY.end());
	const double median = errXY[errXY.size() / 2];
	RecordProperty("median_error_m", std::to_string(median));
	EXPECT_LE(median, 0.15) << "log in " << dir;
	EXPECT_LT(*std::max_element(errXY.begin(), errXY.end()), 1.0) << "log in " << dir;
	// pf-localization writes under its prefix and leaves our outputs as they were.
	EXPECT_TRUE(fs::is_directory(out + "/pf-localization-log_000_0002000"));
	EXPECT_EQ(readTextFile(out + "/map.gridmap.gz"), gridBefore);
}

// observations2map.ini rebuilds our grid from map.simplemap.gz: same resolution, and the
// cells both grids know (not 0.5) agree on free / occupied almost everywhere.
TEST(Observations2map, theOutputFoldersIniRebuildsTheGrid)
{
	LRGC_SKIP_IF_MISSING(senaRawlogPath());
	const char* kObservations2map = "/usr/bin/observations2map";
	if (!fileExists(kObservations2map))
		GTEST_SKIP() << kObservations2map << " not installed (Debian package mrpt-apps)";
	const std::string dir = makeTempDir("o2m_ini_" + std::to_string(::getpid()));
	const std::string out = dir + "/out";
	const auto slam = runProcess(binaryPath("lrgc-slam"),
								 {"--input", senaRawlogPath(), "--out", out, "--quiet"});
	ASSERT_EQ(slam.exitCode, 0) << slam.output;
	const auto o2m = runProcess(
		kObservations2map,
		{out + "/observations2map.ini", out + "/map.simplemap.gz", dir + "/rebuilt"});
	ASSERT_EQ(o2m.exitCode, 0) << o2m.output;
	const auto load = [](const std::string& path)
	{
		mrpt::maps::COccupancyGridMap2D grid;
		mrpt::io::CFileGZInputStream f(path);
		mrpt::serialization::archiveFrom(f) >> grid;
		return grid;
	};
	const auto ours = load(out + "/map.gridmap.gz");
	const auto rebuilt = load(dir + "/rebuilt_gridmap_no00.gridmap");
	EXPECT_FLOAT_EQ(rebuilt.getResolution(), ours.getResolution());
	size_t known = 0, agree = 0;
	for (double y = ours.getYMin(); y < ours.getYMax(); y += ours.getResolution())
		for (double x = ours.getXMin(); x < ours.getXMax(); x += ours.getResolution())
		{
			const float a = ours.getPos(x, y), b = rebuilt.getPos(x, y);
			if (std::abs(a - 0.5f) < 0.05f || std::abs(b - 0.5f) < 0.05f) continue;
			++known;
			agree += (a < 0.5f) == (b < 0.5f);
		}
	ASSERT_GT(known, 10000u);
	EXPECT_GT(double(agree) / double(known), 0.97) << agree << " of " << known;
}
