#include "io/CarmenLine.h"

#include <charconv>
#include <cmath>

namespace lrgc::apps
{
namespace
{
using Kind = TCarmenRecord::Kind;

// Largest reading count accepted: guards the allocation against a garbled count field
// (real scanners have at most a few thousand beams).
constexpr long kMaxReadings = 100000;
// |timestamp| bound [s]: year 5138 as UNIX time; beyond, mrpt::Clock::fromDouble overflows.
constexpr double kMaxTimestamp = 1e11;

void tokenize(std::string_view line, std::vector<std::string_view>& tokens)
{
	tokens.clear();
	size_t i = 0;
	const auto isSpace = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
	while (i < line.size())
	{
		while (i < line.size() && isSpace(line[i])) ++i;
		const size_t start = i;
		while (i < line.size() && !isSpace(line[i])) ++i;
		if (i > start) tokens.push_back(line.substr(start, i - start));
	}
}

bool parseDouble(std::string_view s, double& v)
{
	const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
	return ec == std::errc() && end == s.data() + s.size();
}

bool parseCount(std::string_view s, long& v)
{
	const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
	return ec == std::errc() && end == s.data() + s.size() && v >= 0 && v <= kMaxReadings;
}

// Parses the fields of the record in order; the first failure is remembered.
class CFieldParser
{
public:
	CFieldParser(const std::vector<std::string_view>& tokens, TCarmenRecord& rec)
		: m_tokens(tokens), m_rec(rec)
	{
	}
	bool ok() const { return m_ok; }
	size_t index() const { return m_index; }

	double number(const char* name, bool mustBeFinite)
	{
		double v = 0;
		if (!m_ok) return v;
		const std::string_view tok = m_tokens[m_index];
		if (!parseDouble(tok, v))
			fail(std::string(name) + " '" + std::string(tok) + "' is not a number");
		else if (mustBeFinite && !std::isfinite(v))
			fail(std::string(name) + " '" + std::string(tok) + "' is not finite");
		++m_index;
		return v;
	}
	long count(const char* name)
	{
		long v = 0;
		if (!m_ok) return v;
		const std::string_view tok = m_tokens[m_index];
		if (!parseCount(tok, v))
			fail(std::string(name) + " '" + std::string(tok) + "' is not a count in 0.." +
				 std::to_string(kMaxReadings));
		++m_index;
		return v;
	}
	/** A timestamp [s]: finite and within kMaxTimestamp (beyond, MRPT's clock overflows:
	 * 1e300 became 0.000000). */
	double timestamp(const char* name)
	{
		const double t = number(name, true);
		if (m_ok && !(std::abs(t) <= kMaxTimestamp))
			fail(std::string(name) + " '" + std::string(m_tokens[m_index - 1]) +
				 "' is out of range (|t| <= 1e11 s)");
		return t;
	}
	mrpt::math::TPose2D pose(const char* name)
	{
		mrpt::math::TPose2D p;
		p.x = number(name, true);
		p.y = number(name, true);
		p.phi = number(name, true);
		return p;
	}
	void skip(size_t n) { m_index += n; }
	void check(bool good, const std::string& problem)
	{
		if (m_ok && !good) fail(problem);
	}
	/** Fails unless `needed` more fields exist from the current index. */
	bool require(size_t needed, const char* what)
	{
		if (m_ok && m_index + needed > m_tokens.size())
			fail("too few fields for " + std::string(what) + " (" +
				 std::to_string(m_tokens.size()) + " in all)");
		return m_ok;
	}
	/** After the timestamp: optional hostname and logger_timestamp, nothing more. */
	void trailer()
	{
		if (!m_ok) return;
		const size_t rest = m_tokens.size() - m_index;
		m_rec.fieldsAfterTimestamp = rest;
		if (rest > 2)
			fail(std::to_string(rest - 2) + " unexpected field(s) after logger_timestamp");
		else if (double v = 0; rest == 1 && parseDouble(m_tokens[m_index], v))
			// A hostname alone is accepted; a number there is a field too many before it.
			fail(
				"1 unexpected number after the timestamp (a reading too many, the fields "
				"after the readings shifted?)");
		else if (rest == 2)
		{
			++m_index;  // hostname
			number("logger_timestamp", false);
		}
	}

private:
	void fail(const std::string& problem)
	{
		m_ok = false;
		m_rec.kind = Kind::Malformed;
		m_rec.problem = m_rec.message + ": " + problem;
	}
	const std::vector<std::string_view>& m_tokens;
	TCarmenRecord& m_rec;
	size_t m_index = 1;
	bool m_ok = true;
};

void parseRanges(CFieldParser& p, long n, std::vector<double>& ranges)
{
	ranges.resize(static_cast<size_t>(n));
	for (long i = 0; i < n && p.ok(); ++i) ranges[i] = p.number("range reading", false);
}

void parseFlaser(CFieldParser& p, TCarmenLaser& l)
{
	l.hasOwnGeometry = false;
	l.startAngle = l.angularResolution = l.maxRange = l.tv = l.rv = 0;
	if (!p.require(1, "num_readings")) return;
	const long n = p.count("num_readings");
	if (!p.require(static_cast<size_t>(n) + 7, "the readings, poses and timestamp")) return;
	parseRanges(p, n, l.ranges);
	l.laserPose = p.pose("laser pose");
	l.robotPose = p.pose("odometry pose");
	l.timestamp = p.timestamp("timestamp");
	p.trailer();
}

void parseRobotLaser(CFieldParser& p, TCarmenLaser& l)
{
	l.hasOwnGeometry = true;
	if (!p.require(8, "the laser configuration")) return;
	p.skip(1);  // laser_type
	l.startAngle = p.number("start_angle", true);
	p.number("field_of_view", true);  // implied by start, resolution and count
	l.angularResolution = p.number("angular_resolution", true);
	p.check(l.angularResolution > 0, "angular_resolution must be positive");
	l.maxRange = p.number("maximum_range", true);
	p.check(l.maxRange > 0, "maximum_range must be positive");
	p.number("accuracy", false);
	p.number("remission_mode", false);
	const long n = p.count("num_readings");
	if (!p.require(static_cast<size_t>(n) + 1, "the readings")) return;
	parseRanges(p, n, l.ranges);
	const long m = p.count("num_remissions");
	if (!p.require(static_cast<size_t>(m) + 12, "the remissions, poses and timestamp")) return;
	p.skip(static_cast<size_t>(m));
	l.laserPose = p.pose("laser pose");
	l.robotPose = p.pose("odometry pose");
	l.tv = p.number("tv", false);
	l.rv = p.number("rv", false);
	p.skip(3);  // forward_safety_dist side_safety_dist turn_axis
	l.timestamp = p.timestamp("timestamp");
	p.trailer();
}

void parseOdom(CFieldParser& p, TCarmenOdometry& o)
{
	if (!p.require(7, "pose, velocities and timestamp")) return;
	o.pose = p.pose("pose");
	o.tv = p.number("tv", false);
	o.rv = p.number("rv", false);
	o.accel = p.number("accel", false);
	o.timestamp = p.timestamp("timestamp");
	p.trailer();
}
}  // namespace

void parseCarmenLine(std::string_view line, TCarmenRecord& out)
{
	out.kind = Kind::Ignored;
	out.problem.clear();
	out.fieldsAfterTimestamp = 0;
	tokenize(line, out.tokens);
	if (out.tokens.empty() || out.tokens[0][0] == '#')
	{
		out.message.clear();
		return;
	}
	out.message.assign(out.tokens[0]);
	CFieldParser p(out.tokens, out);
	if (out.message == "FLASER" || out.message == "RLASER")
	{
		out.kind = out.message == "FLASER" ? Kind::FrontLaser : Kind::RearLaser;
		parseFlaser(p, out.laser);
	}
	else if (out.message == "ROBOTLASER1")
	{
		out.kind = Kind::RobotLaser;
		parseRobotLaser(p, out.laser);
	}
	else if (out.message == "ODOM")
	{
		out.kind = Kind::Odometry;
		parseOdom(p, out.odometry);
	}
}

}  // namespace lrgc::apps
