#include "carmen_split.h"

#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/io/CFileGZInputStream.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

namespace lrgc::test
{
namespace
{
// The whole text of a plain or gzip file.
std::string readLogText(const std::string& log)
{
	mrpt::io::CFileGZInputStream in;
	if (!in.open(log)) THROW_EXCEPTION_FMT("cannot open '%s'", log.c_str());
	std::string text;
	char buf[1 << 16];
	for (size_t n; (n = in.Read(buf, sizeof(buf))) > 0;) text.append(buf, n);
	return text;
}
}  // namespace

TSplitCounts splitCarmenLog(const std::string& log, const std::string& firstOut,
							const std::string& secondOut)
{
	const std::string text = readLogText(log);
	std::vector<std::string> header, data;
	for (size_t pos = 0; pos < text.size();)
	{
		size_t end = text.find('\n', pos);
		if (end == std::string::npos) end = text.size();
		std::string line = text.substr(pos, end - pos);
		pos = end + 1;
		if (line.empty()) continue;
		(line[0] == '#' || line.rfind("PARAM", 0) == 0 ? header : data)
			.push_back(std::move(line));
	}
	if (data.empty()) THROW_EXCEPTION_FMT("'%s' holds no data line", log.c_str());
	const size_t half = data.size() / 2;
	std::ofstream a(firstOut), b(secondOut);
	for (const auto& h : header) a << h << '\n', b << h << '\n';
	for (size_t i = 0; i < data.size(); ++i) (i < half ? a : b) << data[i] << '\n';
	if (!a || !b)
		THROW_EXCEPTION_FMT("cannot write '%s' or '%s'", firstOut.c_str(), secondOut.c_str());
	return {header.size(), half, data.size() - half};
}

namespace
{
struct TPose
{
	double x = 0, y = 0, phi = 0;
};
TPose compose(const TPose& a, const TPose& b)
{
	const double c = std::cos(a.phi), s = std::sin(a.phi);
	return {a.x + c * b.x - s * b.y, a.y + s * b.x + c * b.y,
			std::remainder(a.phi + b.phi, 2 * M_PI)};
}
TPose inverse(const TPose& p)
{
	const double c = std::cos(p.phi), s = std::sin(p.phi);
	return {-(c * p.x + s * p.y), -(-s * p.x + c * p.y), -p.phi};
}
// Index of the odometry pose's x among a data line's fields: ODOM x y theta ...; FLASER n
// r_1..r_n laser_x laser_y laser_theta odom_x odom_y odom_theta ipc_t host logger_t.
size_t odometryField(const std::vector<std::string>& f)
{
	if (f[0] == "ODOM") return 1;
	if (f[0] == "FLASER") return 2 + std::stoul(f[1]) + 3;
	THROW_EXCEPTION_FMT("cutCarmenLog: unexpected line kind '%s'", f[0].c_str());
}

std::vector<std::string> fieldsOf(const std::string& line)
{
	std::istringstream words(line);
	return {std::istream_iterator<std::string>(words), {}};
}

// Header lines ('#' comments, PARAM) and empty lines go into every cut as they are.
bool isHeader(const std::vector<std::string>& f)
{
	return f.empty() || f[0][0] == '#' || f[0] == "PARAM";
}

// The line's odometry pose (and FLASER's laser pose, 3 fields before it) moved by `m`:
// p' = m (+) p, written with 6 decimals.
void moveOdometry(std::vector<std::string>& f, const TPose& m)
{
	const size_t o = odometryField(f);
	for (const size_t k : f[0] == "ODOM" ? std::vector<size_t>{o} : std::vector{o - 3, o})
	{
		const TPose p = compose(m, {std::stod(f[k]), std::stod(f[k + 1]), std::stod(f[k + 2])});
		f[k] = mrpt::format("%.6f", p.x), f[k + 1] = mrpt::format("%.6f", p.y),
		f[k + 2] = mrpt::format("%.6f", p.phi);
	}
}

void writeFields(std::ostream& text, const std::vector<std::string>& f)
{
	for (size_t k = 0; k < f.size(); ++k) text << (k ? " " : "") << f[k];
	text << '\n';
}
}  // namespace

double cutCarmenLog(const std::string& log, const std::string& out, double from, double to)
{
	std::ifstream in(log);
	if (!in) THROW_EXCEPTION_FMT("cannot open '%s'", log.c_str());
	std::ostringstream text;
	bool before = false, after = false;
	TPose lastBefore, moved;  // moved = (odometry at from) (+) (odometry at to)^-1
	double shift = 0;
	for (std::string line; std::getline(in, line);)
	{
		std::vector<std::string> f = fieldsOf(line);
		if (isHeader(f))
		{
			text << line << '\n';
			continue;
		}
		const size_t o = odometryField(f);
		const double stamp = std::stod(f[f.size() - 3]);
		const TPose odo{std::stod(f[o]), std::stod(f[o + 1]), std::stod(f[o + 2])};
		if (stamp < from)
		{
			before = true, lastBefore = odo, text << line << '\n';
			continue;
		}
		if (stamp < to) continue;
		if (!after)
			after = true, shift = stamp - from, moved = compose(lastBefore, inverse(odo));
		moveOdometry(f, moved);
		for (const size_t k : {f.size() - 3, f.size() - 1})
			f[k] = mrpt::format("%.6f", std::stod(f[k]) - shift);
		writeFields(text, f);
	}
	if (!before || !after)
		THROW_EXCEPTION_FMT("cutCarmenLog: '%s' has no data on both sides of [%.3f, %.3f)",
							log.c_str(), from, to);
	std::ofstream o(out);
	o << text.str();
	if (!o) THROW_EXCEPTION_FMT("cannot write '%s'", out.c_str());
	return shift;
}

size_t cutCarmenScans(const std::string& log, const std::string& out, size_t first, size_t end,
					  const TOdometryMove& move)
{
	std::istringstream in(readLogText(log));
	std::ostringstream text;
	size_t scan = 0, written = 0;
	const TPose m{move.x, move.y, move.phi};
	for (std::string line; std::getline(in, line);)
	{
		std::vector<std::string> f = fieldsOf(line);
		if (isHeader(f))
		{
			text << line << '\n';
			continue;
		}
		odometryField(f);  // throws on a line kind other than ODOM and FLASER, in range or not
		const bool isScan = f[0] == "FLASER";
		const bool inRange = scan >= first && scan < end;
		scan += isScan;
		if (!inRange) continue;
		written += isScan;
		moveOdometry(f, m);
		writeFields(text, f);
	}
	if (written == 0)
		THROW_EXCEPTION_FMT("cutCarmenScans: '%s' has no scan in [%zu, %zu)", log.c_str(),
							first, end);
	std::ofstream o(out);
	o << text.str();
	if (!o) THROW_EXCEPTION_FMT("cannot write '%s'", out.c_str());
	return written;
}

}  // namespace lrgc::test
