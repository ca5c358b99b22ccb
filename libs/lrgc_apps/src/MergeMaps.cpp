/* lrgc-slam --merge: the keyframe replay and the re-hung trajectory (see MergeMaps.h). */
#include "MergeMaps.h"

#include "ErrorText.h"
#include "lrgc_apps/eval/trajectory.h"

#include <lrgc/common/se2.h>
#include <mrpt/obs/CObservationOdometry.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>

namespace lrgc::apps
{
namespace
{
// The timestamp of a keyframe: its first 2D scan's (the one the builder maps), else the
// frame's first observation's.
mrpt::Clock::time_point frameStamp(const mrpt::obs::CSensoryFrame& sf)
{
	for (const auto& o : sf)
		if (std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(o))
			return o->timestamp;
	return sf.size() > 0 ? (*sf.begin())->timestamp : mrpt::Clock::time_point{};
}
}  // namespace

CKeyframeReplay::CKeyframeReplay(const TSavedMap& map)
	: CLogReader(map.path), m_map(map.keyframes)
{
}

std::optional<TLogEntry> CKeyframeReplay::next()
{
	while (m_next < m_map.size())
	{
		const auto [posePDF, sf] = m_map.get(m_next);
		TLogEntry e;
		e.where = path() + ": keyframe " + std::to_string(m_next);
		if (!posePDF || !sf || sf->size() == 0)
		{
			++m_next;  // nothing to replay; the builder would count it as ignored
			continue;
		}
		if (m_frameDue)
		{
			m_frameDue = false;
			++m_next;
			e.observations = mrpt::obs::CSensoryFrame::Create(*sf);  // shares the scans
			++m_stats.entries, ++m_stats.scans;
			return e;
		}
		auto odo = mrpt::obs::CObservationOdometry::Create();
		odo->sensorLabel = "ODOMETRY";
		odo->timestamp = frameStamp(*sf);
		odo->odometry = mrpt::poses::CPose2D(posePDF->getMeanVal());
		m_poses.push_back({odo->timestamp, odo->odometry.asTPose()});
		e.observation = odo;
		m_frameDue = true;
		++m_stats.entries, ++m_stats.odometry;
		return e;
	}
	return std::nullopt;
}

double CKeyframeReplay::fractionRead() const
{
	return m_map.empty() ? 1.0 : double(m_next) / double(m_map.size());
}

TTrajectory rehangTrajectory(const TTrajectory& dense, const TTrajectory& before,
							 const TTrajectory& after)
{
	if (dense.empty()) return after;
	// The move of each keyframe mapped in the replay, by stamp: (A <- B) local to it,
	//     C_j = K'_j (+) K_j^-1.
	std::vector<std::pair<mrpt::Clock::time_point, mrpt::math::TPose2D>> moves;
	for (const TStampedPose& b : before)
	{
		const auto it =
			std::find_if(after.begin(), after.end(),
						 [&](const TStampedPose& a) { return a.timestamp == b.timestamp; });
		if (it != after.end())
			moves.emplace_back(b.timestamp, compose(it->robotInMap, inverse(b.robotInMap)));
	}
	if (moves.empty()) return after;
	std::sort(moves.begin(), moves.end(),
			  [](const auto& x, const auto& y) { return x.first < y.first; });
	TTrajectory out;
	out.reserve(dense.size());
	for (const TStampedPose& p : dense)
	{
		auto hi = std::lower_bound(moves.begin(), moves.end(), p.timestamp,
								   [](const auto& m, mrpt::Clock::time_point t)
								   { return m.first < t; });
		if (hi == moves.end() || (hi != moves.begin() &&
								  p.timestamp - std::prev(hi)->first < hi->first - p.timestamp))
			hi = std::prev(hi);
		out.push_back({p.timestamp, compose(hi->second, p.robotInMap)});
	}
	return out;
}

TTrajectory savedMapTrajectory(const TSavedMap& map)
{
	namespace fs = std::filesystem;
	std::error_code ec;
	const fs::path file = fs::path(map.path) / "trajectory.tum";
	if (!fs::is_directory(map.path, ec) || !fs::exists(file, ec)) return {};
	TTrajectory out;
	try
	{
		const eval::CTrajectory2D scans = eval::CTrajectory2D::loadFromFile(file.string());
		for (const eval::TTimedPose2D& p : scans.poses())
			out.push_back({mrpt::Clock::fromDouble(p.t), p.pose});
	}
	catch (const std::exception& e)
	{
		throw std::runtime_error("--merge '" + file.string() + "': " + oneLineError(e));
	}
	return out;
}

}  // namespace lrgc::apps
