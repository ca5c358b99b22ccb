#include "io_test_files.h"

#include <mrpt/core/format.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>

#include <fstream>
#include <iterator>
#include <stdexcept>

namespace lrgc::test
{
std::string readFileBytes(const std::string& path)
{
	std::ifstream f(path, std::ios::binary);
	if (!f) throw std::runtime_error("cannot read " + path);
	return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

void writeFileBytes(const std::string& path, const std::string& bytes)
{
	std::ofstream f(path, std::ios::binary | std::ios::trunc);
	f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
	if (!f) throw std::runtime_error("cannot write " + path);
}

std::string readUncompressed(const std::string& path)
{
	mrpt::io::CFileGZInputStream in(path);
	std::string out;
	char buf[1 << 16];
	while (const size_t n = in.Read(buf, sizeof(buf)))
	{
		if (n > sizeof(buf)) throw std::runtime_error("corrupt gzip " + path);
		out.append(buf, n);
	}
	return out;
}

void writeGzFile(const std::string& path, const std::string& bytes)
{
	mrpt::io::CFileGZOutputStream out;
	if (!out.open(path)) throw std::runtime_error("cannot write " + path);
	if (out.Write(bytes.data(), bytes.size()) != bytes.size())
		throw std::runtime_error("short write " + path);
	out.close();
}

std::string carmenStamp(double t)
{
	return mrpt::format("%.6f nohost %.6f", t, t);
}

namespace
{
std::string ranges(const std::vector<double>& r)
{
	std::string s = std::to_string(r.size());
	for (const double v : r) s += mrpt::format(" %.2f", v);
	return s;
}
std::string pose(const mrpt::math::TPose2D& p)
{
	return mrpt::format("%.6f %.6f %.6f", p.x, p.y, p.phi);
}
}  // namespace

std::string flaserLine(const std::vector<double>& r, const mrpt::math::TPose2D& laser,
					   const mrpt::math::TPose2D& robot, double t, const std::string& message)
{
	return message + " " + ranges(r) + " " + pose(laser) + " " + pose(robot) + " " +
		   carmenStamp(t) + "\n";
}

std::string odomLine(const mrpt::math::TPose2D& p, double t)
{
	return "ODOM " + pose(p) + " 0.300000 0.100000 0.000000 " + carmenStamp(t) + "\n";
}

std::string robotLaser1Line(double startAngle, double fov, double resolution, double maxRange,
							const std::vector<double>& r, const mrpt::math::TPose2D& laser,
							const mrpt::math::TPose2D& robot, double t)
{
	return mrpt::format("ROBOTLASER1 0 %.6f %.6f %.6f %.2f 0.01 0 ", startAngle, fov,
						resolution, maxRange) +
		   ranges(r) + " 2 0.5 0.5 " + pose(laser) + " " + pose(robot) +
		   " 0.100000 0.200000 0.5 0.3 1.0 " + carmenStamp(t) + "\n";
}

}  // namespace lrgc::test
