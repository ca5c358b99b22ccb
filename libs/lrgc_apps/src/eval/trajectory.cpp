/* Timed 2D trajectories: parsing of TUM and `t x y phi` files, and pose look-up by time
 * (exact match within a tolerance, else linear interpolation on a time-sorted index). */
#include "lrgc_apps/eval/trajectory.h"

#include "ErrorText.h"

#include <mrpt/core/exceptions.h>
#include <mrpt/math/wrap2pi.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <numeric>
#include <sstream>

namespace lrgc::apps::eval
{
std::string readTextFile(const std::string& path)
{
	std::ifstream in(path, std::ios::binary);
	if (!in) THROW_EXCEPTION_FMT("%s: cannot open file for reading", path.c_str());
	std::ostringstream ss;
	ss << in.rdbuf();
	if (in.bad()) THROW_EXCEPTION_FMT("%s: read error", path.c_str());
	return ss.str();
}

std::string userMessage(const std::exception& e)
{
	return oneLineError(e);
}

bool isBlankOrComment(const std::string& line)
{
	const auto pos = line.find_first_not_of(" \t\r\n");
	return pos == std::string::npos || line[pos] == '#';
}

void forEachDataLine(const std::string& text,
					 const std::function<void(const std::string& line, std::size_t lineNo)>& f)
{
	std::size_t lineNo = 0, begin = 0;
	while (begin < text.size())
	{
		auto end = text.find('\n', begin);
		if (end == std::string::npos) end = text.size();
		++lineNo;
		const std::string line = text.substr(begin, end - begin);
		if (!isBlankOrComment(line)) f(line, lineNo);
		begin = end + 1;
	}
}

std::vector<double> parseNumberLine(const std::string& line, const std::string& sourceName,
									std::size_t lineNo)
{
	std::vector<double> out;
	std::istringstream ss(line);
	std::string token;
	while (ss >> token)
	{
		const char* s = token.c_str();
		char* end = nullptr;
		errno = 0;
		const double v = std::strtod(s, &end);
		if (end == s || *end != '\0' || !std::isfinite(v) || errno == ERANGE)
			THROW_EXCEPTION_FMT("%s:%zu: '%s' is not a finite number", sourceName.c_str(),
								lineNo, token.c_str());
		out.push_back(v);
	}
	return out;
}

std::optional<double> yawFromQuaternion(double qx, double qy, double qz, double qw)
{
	const double n = std::sqrt(qx * qx + qy * qy + qz * qz + qw * qw);
	if (!(n > 1e-9)) return std::nullopt;
	qx /= n, qy /= n, qz /= n, qw /= n;
	// z-y-x Euler yaw: atan2(2 (qw qz + qx qy), 1 - 2 (qy^2 + qz^2)) [rad]
	return std::atan2(2 * (qw * qz + qx * qy), 1 - 2 * (qy * qy + qz * qz));
}

CTrajectory2D::CTrajectory2D(std::vector<TTimedPose2D> poses) : m_poses(std::move(poses))
{
	for (const auto& p : m_poses)
		ASSERTMSG_(std::isfinite(p.t), "CTrajectory2D: non-finite timestamp");
	m_byTime.resize(m_poses.size());
	std::iota(m_byTime.begin(), m_byTime.end(), std::size_t{0});
	std::stable_sort(m_byTime.begin(), m_byTime.end(),
					 [this](std::size_t a, std::size_t b)
					 { return m_poses[a].t < m_poses[b].t; });
}

CTrajectory2D CTrajectory2D::loadFromFile(const std::string& path)
{
	return parse(readTextFile(path), path);
}

CTrajectory2D CTrajectory2D::parse(const std::string& text, const std::string& sourceName)
{
	std::vector<TTimedPose2D> poses;
	std::size_t columns = 0;  // 8 (TUM) or 4 (t x y phi), fixed by the first pose line
	forEachDataLine(
		text,
		[&](const std::string& line, std::size_t lineNo)
		{
			const auto v = parseNumberLine(line, sourceName, lineNo);
			if (columns == 0)
			{
				if (v.size() != 8 && v.size() != 4)
					THROW_EXCEPTION_FMT(
						"%s:%zu: expected 8 numbers (TUM: t x y z qx qy qz qw) or 4 numbers "
						"(t x y phi), got %zu",
						sourceName.c_str(), lineNo, v.size());
				columns = v.size();
			}
			if (v.size() != columns)
				THROW_EXCEPTION_FMT(
					"%s:%zu: expected %zu numbers (%s) like the first pose line, got %zu",
					sourceName.c_str(), lineNo, columns,
					columns == 8 ? "t x y z qx qy qz qw" : "t x y phi", v.size());
			TTimedPose2D p;
			p.t = v[0];
			p.line = lineNo;
			p.pose.x = v[1];
			p.pose.y = v[2];
			if (columns == 8)
			{
				const auto yaw = yawFromQuaternion(v[4], v[5], v[6], v[7]);
				if (!yaw)
					THROW_EXCEPTION_FMT("%s:%zu: zero quaternion (qx qy qz qw all ~0)",
										sourceName.c_str(), lineNo);
				p.pose.phi = *yaw;
			}
			else
				p.pose.phi = mrpt::math::wrapToPi(v[3]);
			poses.push_back(p);
		});
	if (poses.empty()) THROW_EXCEPTION_FMT("%s: no pose line in the file", sourceName.c_str());
	return CTrajectory2D(std::move(poses));
}

double CTrajectory2D::earliestTime() const
{
	ASSERTMSG_(!m_byTime.empty(), "CTrajectory2D::earliestTime: empty trajectory");
	return m_poses[m_byTime.front()].t;
}

double CTrajectory2D::latestTime() const
{
	ASSERTMSG_(!m_byTime.empty(), "CTrajectory2D::latestTime: empty trajectory");
	return m_poses[m_byTime.back()].t;
}

std::size_t CTrajectory2D::backwardTimeJumps() const
{
	std::size_t n = 0;
	for (std::size_t i = 1; i < m_poses.size(); ++i)
		if (m_poses[i].t < m_poses[i - 1].t) ++n;
	return n;
}

std::optional<TPoseAtTime> CTrajectory2D::poseAt(double t, double exactTolerance_s) const
{
	if (m_byTime.empty() || !std::isfinite(t)) return std::nullopt;
	const auto timeOf = [this](std::size_t k) { return m_poses[m_byTime[k]].t; };
	// First sorted position with time >= t.
	const auto it = std::lower_bound(m_byTime.begin(), m_byTime.end(), t,
									 [this](std::size_t idx, double value)
									 { return m_poses[idx].t < value; });
	const std::size_t k = static_cast<std::size_t>(it - m_byTime.begin());

	// Exact match: the closest timestamp within the tolerance; on a tie the first in file
	// order. Candidates are the sorted neighbours of position k on both sides.
	std::optional<std::size_t> best;
	double bestDt = 0;
	const auto consider = [&](std::size_t j)
	{
		const std::size_t idx = m_byTime[j];
		const double dt = std::abs(timeOf(j) - t);
		if (!best || dt < bestDt || (dt == bestDt && idx < *best)) best = idx, bestDt = dt;
	};
	for (std::size_t j = k; j-- > 0 && t - timeOf(j) <= exactTolerance_s;) consider(j);
	for (std::size_t j = k; j < m_byTime.size() && timeOf(j) - t <= exactTolerance_s; ++j)
		consider(j);
	if (best) return TPoseAtTime{m_poses[*best].pose, TPoseLookup::Exact};

	if (k == 0 || k == m_byTime.size()) return std::nullopt;  // outside the time span
	const TTimedPose2D& a = m_poses[m_byTime[k - 1]];
	const TTimedPose2D& b = m_poses[m_byTime[k]];
	const double s = (t - a.t) / (b.t - a.t);  // in (0, 1): a.t < t < b.t here
	// Linear in x, y; phi along the shorter arc: phi_a + s * wrap(phi_b - phi_a) [rad].
	mrpt::math::TPose2D p;
	p.x = a.pose.x + s * (b.pose.x - a.pose.x);
	p.y = a.pose.y + s * (b.pose.y - a.pose.y);
	p.phi =
		mrpt::math::wrapToPi(a.pose.phi + s * mrpt::math::wrapToPi(b.pose.phi - a.pose.phi));
	return TPoseAtTime{p, TPoseLookup::Interpolated};
}

}  // namespace lrgc::apps::eval
