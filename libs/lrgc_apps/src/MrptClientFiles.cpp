#include "MrptClientFiles.h"

#include "lrgc_apps/RunOutputs.h"
#include "atomic_file.h"

#include <mrpt/core/format.h>

#include <cmath>
#include <filesystem>

namespace lrgc::apps
{
namespace
{
constexpr double kStartSpreadXY = 0.5;     // [m] half width of the initial particle box
constexpr double kStartSpreadYawDeg = 10;  // [deg] half width of its heading interval

std::string absolutePath(const std::string& path)
{
	std::error_code ec;
	const auto p = std::filesystem::absolute(path, ec);
	return ec ? path : p.lexically_normal().string();
}

// The particle filter, as MRPT's sample config_files/pf-localization/localization_demo.ini
// names its keys, with the settings tests/pf_localization_test.cpp measured on SENA.
const char* const kFilterSections =
	"[KLD_options]\n"
	"KLD_binSize_PHI_deg = 10\n"
	"KLD_binSize_XY = 0.10\n"
	"KLD_delta = 0.01\n"
	"KLD_epsilon = 0.01\n"
	"KLD_maxSampleSize = 4000\n"
	"KLD_minSampleSize = 150\n"
	"KLD_minSamplesPerBin = 0\n"
	"\n[PF_options]\n"
	"PF_algorithm = 0\n"
	"resamplingMethod = 0\n"
	"adaptiveSampleSize = 1\n"
	"BETA = 0.5\n"
	"sampleSize = 1\n"
	"pfAuxFilterOptimal_MaximumSearchSamples = 10\n"
	"\n# Odometry noise for observations-only rawlogs (CObservationOdometry).\n"
	"[DummyOdometryParams]\n"
	"minStdXY = 0.10\n"
	"minStdPHI = 2.0\n";
}  // namespace

std::string pfLocalizationIni(const std::string& outDir, const std::string& rawlog,
							  const mrpt::math::TPose2D& startPose, double resolution)
{
	const std::string dir = absolutePath(outDir);
	const std::string map = (std::filesystem::path(dir) / "map.gridmap.gz").string();
	std::string rawlogLines;
	if (!rawlog.empty())
		rawlogLines = "rawlog_file = " + absolutePath(rawlog) + "\n";
	else
		rawlogLines =
			"# The input was not an MRPT rawlog and no conversion was written: make one with\n"
			"#   lrgc-slam --input LOG --save-rawlog LOG.rawlog\n"
			"# and give its path here (or as pf-localization's second argument).\n"
			"rawlog_file =\n";
	const double yawDeg = startPose.phi * 180 / M_PI;
	return "# pf-localization (MRPT) on the map of this folder, written by lrgc-slam. Run it,\n"
		   "# headless, from any folder:\n"
		   "#   pf-localization " +
		   dir +
		   "/pf-localization.ini </dev/null\n"
		   "# Its estimates are the \"PDF estimation\" lines it prints at each step. The "
		   "map's\n"
		   "# origin is the first mapped scan's pose: the particles start around the first\n"
		   "# pose of trajectory.tum.\n\n" +
		   kFilterSections +
		   "\n[LocalizationExperiment]\n"
		   "use_3D_poses = false\n"
		   "map_file = " +
		   map + "\n" + rawlogLines +
		   "# A prefix: pf-localization writes PREFIX_000_0002000/ (emptied first) and\n"
		   "# PREFIX_SUMMARY.txt, beside lrgc-slam's files, which it does not touch.\n"
		   "logOutput_dir = " +
		   dir +
		   "/pf-localization-log\n"
		   "3DSceneFrequency = -1\n"
		   "SHOW_PROGRESS_3D_REAL_TIME = false\n"
		   "experimentRepetitions = 1\n"
		   "particles_count = 2000\n"
		   "# 1: uniform in the box below (0 would keep only the box's free cells).\n"
		   "init_PDF_mode = 1\n" +
		   mrpt::format("init_PDF_min_x = %.6f\ninit_PDF_max_x = %.6f\n",
						startPose.x - kStartSpreadXY, startPose.x + kStartSpreadXY) +
		   mrpt::format("init_PDF_min_y = %.6f\ninit_PDF_max_y = %.6f\n",
						startPose.y - kStartSpreadXY, startPose.y + kStartSpreadXY) +
		   mrpt::format("init_PDF_min_yaw_deg = %.6f\ninit_PDF_max_yaw_deg = %.6f\n",
						yawDeg - kStartSpreadYawDeg, yawDeg + kStartSpreadYawDeg) +
		   "\n[MetricMap]\n"
		   "occupancyGrid_count = 1\n"
		   "likelihoodMapSelection = -1\n"
		   "\n[MetricMap_occupancyGrid_00_creationOpts]\n" +
		   mrpt::format("resolution = %.6f\n", resolution) +
		   "\n[MetricMap_occupancyGrid_00_insertOpts]\n"
		   "maxDistanceInsertion = 15\n"
		   "\n[MetricMap_occupancyGrid_00_likelihoodOpts]\n"
		   "likelihoodMethod = 4\n"
		   "LF_decimation = 5\n"
		   "LF_stdHit = 0.20\n"
		   "LF_maxCorrsDistance = 0.30\n"
		   "LF_zHit = 0.95\n"
		   "LF_zRandom = 0.05\n"
		   "LF_maxRange = 80\n"
		   "LF_alternateAverageMethod = 0\n";
}

std::string observations2mapIni(double resolution, double maxRange)
{
	return "# observations2map (MRPT): the occupancy grid of this folder's map.simplemap.gz\n"
		   "# with lrgc-slam's grid settings, written by lrgc-slam. Run it as\n"
		   "#   observations2map observations2map.ini map.simplemap.gz PREFIX </dev/null\n"
		   "# (PREFIX_gridmap_no00.gridmap is the grid).\n"
		   "[MappingApplication]\n"
		   "occupancyGrid_count = 1\n"
		   "\n[MappingApplication_occupancyGrid_00_creationOpts]\n" +
		   mrpt::format("resolution = %.6f\n", resolution) +
		   "\n[MappingApplication_occupancyGrid_00_insertOpts]\n" +
		   mrpt::format("maxDistanceInsertion = %.6f\n", maxRange);
}

void writeMrptClientFiles(const TRunOutputsSnapshot& s, const std::string& outDir)
{
	namespace fs = std::filesystem;
	const mrpt::math::TPose2D start =
		s.trajectory.empty() ? mrpt::math::TPose2D() : s.trajectory.front().robotInMap;
	writeTextFileAtomically(
		(fs::path(outDir) / "pf-localization.ini").string(),
		pfLocalizationIni(outDir, s.run.mrptRawlog, start, s.gridSettings.resolution));
	writeTextFileAtomically(
		(fs::path(outDir) / "observations2map.ini").string(),
		observations2mapIni(s.gridSettings.resolution, s.gridSettings.maxRayLength));
}

}  // namespace lrgc::apps
