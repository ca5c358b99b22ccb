/* The ACES sessions of issue 29's tests (aces_pieces_test.cpp, merge_maps_test.cpp): the
 * relation metric over trajectories of sessions of one log, each trajectory.tum one session. */
#pragma once

#include <lrgc_apps/eval/relation_metric.h>
#include <lrgc_apps/eval/trajectory.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "app_runner.h"
#include "carmen_split.h"

namespace lrgc::test
{
namespace eval = lrgc::apps::eval;

/** Issue 29's two ACES sessions: A = scans [0, kSessionAEnd), B from scan kSessionBStart, B's
 * odometry moved by kMoveB (+37 m, -12 m, 130 deg) into a frame of its own. */
constexpr size_t kSessionAEnd = 1474, kSessionBStart = 2934;
inline const TOdometryMove kMoveB{37.0, -12.0, 130.0 * M_PI / 180.0};

/** The first and last stamps of a trajectory.tum [s]. */
inline std::pair<double, double> span(const std::string& tum)
{
	std::istringstream in(readTextFile(tum));
	double first = -1, last = -1;
	for (std::string line; std::getline(in, line);)
		if (!line.empty() && line[0] != '#')
		{
			last = std::stod(line.substr(0, line.find(' ')));
			if (first < 0) first = last;
		}
	return {first, last};
}

/** Which relations to evaluate: those with both ends within one session's span, those with
 * their ends in two sessions, or both (the metric would interpolate across a gap). */
enum class Relations
{
	WithinSessions,
	AcrossSessions,
	All
};

/** The relation metric of the trajectories concatenated, over `which` relations. */
inline eval::TRelationEvaluation evaluate(const std::vector<std::string>& tums,
										  const std::string& relationsFile,
										  const std::string& tmp, size_t& considered,
										  Relations which = Relations::All)
{
	std::string both;
	std::vector<std::pair<double, double>> spans;
	for (const auto& t : tums) both += readTextFile(t), spans.push_back(span(t));
	writeTextFile(tmp, both);
	const auto session = [&](double t)
	{
		for (size_t i = 0; i < spans.size(); ++i)
			if (t >= spans[i].first && t <= spans[i].second) return int(i);
		return -1;
	};
	const auto wanted = [&](const eval::TRelation& r)
	{
		const int a = session(r.t1), b = session(r.t2);
		if (a < 0 || b < 0) return false;
		return which == Relations::All || (which == Relations::WithinSessions) == (a == b);
	};
	auto relations = eval::loadRelations(relationsFile);
	relations.erase(std::remove_if(relations.begin(), relations.end(),
								   [&](const eval::TRelation& r) { return !wanted(r); }),
					relations.end());
	considered = relations.size();
	return eval::evaluateRelations(eval::CTrajectory2D::loadFromFile(tmp), relations);
}
}  // namespace lrgc::test
