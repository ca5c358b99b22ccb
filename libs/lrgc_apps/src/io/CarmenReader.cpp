#include "io/CarmenReader.h"

#include <lrgc/common/se2.h>
#include <mrpt/core/format.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/poses/CPose3D.h>

#include <algorithm>
#include <cctype>
#include <cmath>

namespace lrgc::apps
{
using mrpt::obs::CObservation2DRangeScan;
using mrpt::obs::CObservationOdometry;
using Kind = TCarmenRecord::Kind;

namespace
{
constexpr size_t kReadChunk = 64 * 1024;
constexpr size_t kMaxLineBytes = 16 * 1024 * 1024;
// Half the 1 cm quantisation of CARMEN ranges: a reading within it of the limit is a
// no-return (see LogReaderOptions.h).
constexpr double kNoReturnTolerance = 0.005;  // [m]

// The name a line is counted under in TLogReadStats::contents: its message if that looks
// like one (an upper-case identifier), so that a line of binary junk adds no odd name.
std::string contentsKey(const std::string& message)
{
	const bool identifier =
		!message.empty() && message.size() <= 32 &&
		std::all_of(message.begin(), message.end(),
					[](unsigned char c)
					{ return std::isupper(c) || std::isdigit(c) || c == '_'; });
	return (identifier ? message : std::string("other")) + " lines";
}
}  // namespace

CCarmenReader::CCarmenReader(const std::string& path, const TLogReaderOptions& options)
	: CLogReader(path), m_options(options), m_in(path)
{
}

namespace
{
// A UTF-8 byte order mark (written by some editors) before the first line is no part of it.
void dropByteOrderMark(std::string& line)
{
	if (line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
}
}  // namespace

bool CCarmenReader::readLine(std::string& line)
{
	while (true)
	{
		const size_t nl = m_buffer.find('\n', m_bufferPos);
		if (nl != std::string::npos)
		{
			line.assign(m_buffer, m_bufferPos, nl - m_bufferPos);
			m_bufferPos = nl + 1;
			if (++m_lineNumber == 1) dropByteOrderMark(line);
			return true;
		}
		if (m_in.reachedEnd())
		{
			if (m_bufferPos >= m_buffer.size()) return false;
			line.assign(m_buffer, m_bufferPos, std::string::npos);  // last line, no '\n'
			m_bufferPos = m_buffer.size();
			m_lineEndedFile = true;
			if (++m_lineNumber == 1) dropByteOrderMark(line);
			return true;
		}
		m_buffer.erase(0, m_bufferPos);
		m_bufferPos = 0;
		if (m_buffer.size() > kMaxLineBytes)
			throw CLogReadError(
				path(), "line " + std::to_string(m_lineNumber + 1),
				"a line longer than 16 MiB: this is no CARMEN text past this point");
		const size_t old = m_buffer.size();
		m_buffer.resize(old + kReadChunk);
		m_buffer.resize(old + m_in.Read(&m_buffer[old], kReadChunk));
	}
}

std::optional<TLogEntry> CCarmenReader::next()
{
	try
	{
		std::string line;
		while (m_pending.empty() && !m_finished)
		{
			if (readLine(line))
				processLine(line);
			else
			{
				m_finished = true;
				reportUnlistedWarnings();
				m_in.verifyCompleteAtEnd();
			}
		}
	}
	catch (const CLogReadError&)
	{
		m_finished = true;
		m_pending.clear();
		reportUnlistedWarnings();
		throw;
	}
	if (m_pending.empty()) return std::nullopt;
	TLogEntry entry = std::move(m_pending.front());
	m_pending.pop_front();
	++m_stats.entries;
	return entry;
}

void CCarmenReader::processLine(const std::string& line)
{
	const std::string place = "line " + std::to_string(m_lineNumber);
	parseCarmenLine(line, m_record);
	// The last line without its end of line may be cut short, even inside a number.
	const bool unterminated = m_lineEndedFile;
	switch (m_record.kind)
	{
		case Kind::Ignored:
			++m_stats.ignoredLines;
			if (!m_record.message.empty()) ++m_stats.contents[contentsKey(m_record.message)];
			return;
		case Kind::Malformed:
			++m_stats.skippedLines;
			++m_stats.contents["malformed " + contentsKey(m_record.message)];
			warn(Problem::MalformedLine, place,
				 "malformed " + m_record.problem + "; line skipped" +
					 (unterminated ? " (the last line, without end of line: the file may be "
									 "truncated)"
								   : ""));
			return;
		default:
			break;
	}
	if (unterminated && m_record.fieldsAfterTimestamp == 0)
	{
		++m_stats.skippedLines;
		++m_stats.contents["malformed " + contentsKey(m_record.message)];
		warn(Problem::MalformedLine, place,
			 m_record.message +
				 ": the last line ends inside its timestamp, without end of line: the file "
				 "is truncated; line skipped");
		return;
	}
	++m_stats.contents[contentsKey(m_record.message)];
	if (m_record.kind == Kind::Odometry)
		addOdometry(m_record.odometry, place);
	else
		addLaser(m_record.laser, place);
}

void CCarmenReader::addOdometry(const TCarmenOdometry& odom, const std::string& place)
{
	auto obs = CObservationOdometry::Create();
	obs->sensorLabel = "ODOMETRY";
	obs->timestamp = mrpt::Clock::fromDouble(odom.timestamp);
	obs->odometry = mrpt::poses::CPose2D(odom.pose);
	obs->hasVelocities = true;
	obs->velocityLocal = mrpt::math::TTwist2D(odom.tv, 0, odom.rv);
	checkTimeOrder(m_record.message, obs->timestamp, place, false);
	++m_stats.odometry;
	m_pending.push_back(TLogEntry{nullptr, nullptr, obs, path() + ": " + place});
}

namespace
{
/* The scan's ranges from a CARMEN line's readings [m]: r >= maxRange - 5 mm (or +inf) and
 * r == 0 are no-returns (invalid, counted in `noReturns`); NaN and r < 0 are invalid and
 * returned as the count of bad readings, the first at `firstBad`. */
size_t setRanges(CObservation2DRangeScan& scan, const std::vector<double>& ranges,
				 double maxRange, size_t& noReturns, size_t& firstBad)
{
	const double noReturnFrom = maxRange - kNoReturnTolerance;
	size_t bad = 0;
	for (size_t i = 0; i < ranges.size(); ++i)
	{
		const double r = ranges[i];
		if (std::isnan(r) || r < 0)
		{
			if (bad++ == 0) firstBad = i;
			scan.setScanRange(i, 0);
			scan.setScanRangeValidity(i, false);
		}
		else if (r >= noReturnFrom || r == 0)
		{
			++noReturns;
			scan.setScanRange(i, r == 0 ? 0.f : static_cast<float>(maxRange));
			scan.setScanRangeValidity(i, false);
		}
		else
		{
			scan.setScanRange(i, static_cast<float>(r));
			scan.setScanRangeValidity(i, true);
		}
	}
	return bad;
}
}  // namespace

void CCarmenReader::addLaser(const TCarmenLaser& laser, const std::string& place)
{
	const auto stamp = mrpt::Clock::fromDouble(laser.timestamp);
	const std::string& message = m_record.message;

	// The robot's odometry at this scan: the pose recorded inside this same line.
	auto odo = CObservationOdometry::Create();
	odo->sensorLabel = "ODOMETRY";
	odo->timestamp = stamp;
	odo->odometry = mrpt::poses::CPose2D(laser.robotPose);
	odo->hasVelocities = laser.hasOwnGeometry;
	if (laser.hasOwnGeometry) odo->velocityLocal = mrpt::math::TTwist2D(laser.tv, 0, laser.rv);
	++m_stats.odometry;
	m_pending.push_back(TLogEntry{nullptr, nullptr, odo, path() + ": " + place});

	checkTimeOrder(message, stamp, place, true);
	const size_t n = laser.ranges.size();
	if (n < 2)
	{
		++m_stats.emptyScans;
		warn(Problem::EmptyScan, place,
			 mrpt::format("%s with %zu reading(s): scan skipped, its odometry kept",
						  message.c_str(), n));
		return;
	}

	// Beam fan in the laser frame: beam i at start + i * step [rad], counter-clockwise.
	double start = -M_PI / 2, step = M_PI / double(n - 1),
		   maxRange = m_options.carmen_max_range_m;
	if (laser.hasOwnGeometry)
	{
		start = laser.startAngle;
		step = laser.angularResolution;
		maxRange = laser.maxRange;
	}
	else if (n == 180)
		step = m_options.carmen_180_beams_fov / double(n - 1);
	const double aperture = step * double(n - 1);
	// MRPT's fan is symmetric about the sensor's x axis: rotate the sensor by the centre.
	const double centre = start + aperture / 2;
	const mrpt::math::TPose2D laserInRobot = lrgc::between(laser.robotPose, laser.laserPose);

	auto scan = CObservation2DRangeScan::Create();
	scan->sensorLabel = m_record.kind == Kind::RearLaser ? "REAR_LASER" : "LASER";
	scan->timestamp = stamp;
	scan->aperture = static_cast<float>(aperture);
	scan->rightToLeft = true;
	scan->maxRange = static_cast<float>(maxRange);
	scan->sensorPose =
		mrpt::poses::CPose3D(laserInRobot.x, laserInRobot.y, 0,
							 mrpt::math::wrapToPi(laserInRobot.phi + centre), 0, 0);
	scan->resizeScan(n);

	size_t firstBad = 0;
	const size_t bad =
		setRanges(*scan, laser.ranges, maxRange, m_stats.noReturnRanges, firstBad);
	if (bad > 0)
	{
		m_stats.invalidRanges += bad;
		warn(Problem::BadRanges, place,
			 mrpt::format(
				 "%s: %zu NaN or negative reading(s) of %zu marked invalid (first: beam %zu, "
				 "%g)",
				 message.c_str(), bad, n, firstBad, laser.ranges[firstBad]));
	}
	++m_stats.scans;
	m_pending.push_back(TLogEntry{nullptr, nullptr, scan, path() + ": " + place});
}

}  // namespace lrgc::apps
