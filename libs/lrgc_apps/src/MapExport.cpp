#include "lrgc_apps/MapExport.h"

#include "atomic_file.h"

#include <mrpt/img/CImage.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/serialization/CArchive.h>

#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

namespace lrgc::apps
{
namespace
{
template <class T>
void writeArchiveGz(const T& object, const std::string& path)
{
	writeArchiveAtomically(path, TFileCompression::Gzip,
						   [&](mrpt::serialization::CArchive& arch) { arch << object; });
}

// ROS map_server trinary values for a cell's occupancy probability p(occupied).
// (MRPT's COccupancyGridMap2D::getCell() returns the complement, p(free).)
uint8_t rosPixel(float pOccupied)
{
	if (pOccupied > 0.65f) return 0;     // occupied: black
	if (pOccupied < 0.196f) return 254;  // free: white
	return 205;                          // unknown: grey
}
}  // namespace

void writeGridmap(const mrpt::maps::COccupancyGridMap2D& grid, const std::string& path)
{
	writeArchiveGz(grid, path);
}

void writeGridPng(const mrpt::maps::COccupancyGridMap2D& grid, const std::string& path)
{
	mrpt::img::CImage img;
	// MRPT already puts the grid's top (max y) in image row 0: north up, as map.pgm (tested).
	grid.getAsImage(img, /*verticalFlip=*/false, /*forceRGB=*/false);
	// Encoded in memory (OpenCV's PNG encoder with its defaults, as CImage::saveToFile), then
	// written with checked writes: imwrite's stdio flush at fclose cannot be checked.
	std::vector<uchar> png;
	if (!cv::imencode(".png", img.asCvMatRef(), png))
		THROW_EXCEPTION_FMT("cannot encode the map image for '%s'", path.c_str());
	writeTextFileAtomically(
		path, std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
}

void writeRosMap(const mrpt::maps::COccupancyGridMap2D& grid, const std::string& stemPath)
{
	using Cell = mrpt::maps::COccupancyGridMap2D::cellType;
	constexpr int kMin = std::numeric_limits<Cell>::min(),
				  kMax = std::numeric_limits<Cell>::max();
	// The pixel of every value a cell can hold, once (getCell per cell is 3 M look-ups of the
	// same table on a 1500 x 2000 grid): the complement of MRPT's p(free) of that log-odds.
	std::vector<char> pixelOf(kMax - kMin + 1);
	for (int v = kMin; v <= kMax; ++v)
		pixelOf[v - kMin] = static_cast<char>(
			rosPixel(1.0f - mrpt::maps::COccupancyGridMap2D::l2p(static_cast<Cell>(v))));
	const unsigned w = grid.getSizeX(), h = grid.getSizeY();
	std::string pgm = "P5\n" + std::to_string(w) + " " + std::to_string(h) + "\n255\n";
	const size_t header = pgm.size();
	pgm.resize(header + size_t(w) * h);
	// PGM rows run top (max y) to bottom (min y); grid row 0 is min y.
	for (unsigned r = 0; r < h; ++r)
	{
		const Cell* row = grid.getRow(static_cast<int>(h - 1 - r));
		char* out = &pgm[header + size_t(r) * w];
		for (unsigned c = 0; c < w; ++c) out[c] = pixelOf[int(row[c]) - kMin];
	}
	const std::string pgmPath = stemPath + ".pgm";
	writeTextFileAtomically(pgmPath, pgm);

	std::ostringstream yaml;
	yaml.precision(9);
	yaml << "image: " << std::filesystem::path(pgmPath).filename().string() << "\n"
		 << "resolution: " << grid.getResolution() << "\n"
		 << "origin: [" << grid.getXMin() << ", " << grid.getYMin() << ", 0.0]\n"
		 << "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
	writeTextFileAtomically(stemPath + ".yaml", yaml.str());
}

void writeSimplemap(const mrpt::maps::CSimpleMap& map, const std::string& path)
{
	writeArchiveGz(map, path);
}

void writeTrajectoryTum(const TTrajectory& trajectory, const std::string& path)
{
	writeTextFileAtomically(path, trajectoryTumText(trajectory));
}

std::string trajectoryTumText(const TTrajectory& trajectory)
{
	std::string out;
	out.reserve(trajectory.size() * 80);
	char line[160];
	for (const auto& p : trajectory)
	{
		// Yaw-only rotation as a unit quaternion: (0, 0, sin(phi/2), cos(phi/2)).
		const double half = 0.5 * p.robotInMap.phi;
		std::snprintf(line, sizeof(line), "%.6f %.6f %.6f 0 0 0 %.9f %.9f\n",
					  mrpt::Clock::toDouble(p.timestamp), p.robotInMap.x, p.robotInMap.y,
					  std::sin(half), std::cos(half));
		out += line;
	}
	return out;
}

void writeGraph(const mrpt::graphs::CNetworkOfPoses2DInf& graph, const std::string& path)
{
	// MRPT's saveToTextFile writes through an unchecked std::ofstream: render in memory.
	std::ostringstream text;
	graph.writeAsText(text);
	writeTextFileAtomically(path, text.str());
}

}  // namespace lrgc::apps
