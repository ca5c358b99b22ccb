#include "io/RawlogReader.h"

#include <mrpt/core/format.h>
#include <mrpt/maps/registerAllClasses.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/registerAllClasses.h>

namespace lrgc::apps
{
using mrpt::obs::CActionCollection;
using mrpt::obs::CObservation;
using mrpt::obs::CObservation2DRangeScan;
using mrpt::obs::CSensoryFrame;
using mrpt::serialization::CSerializable;

CRawlogReader::CRawlogReader(const std::string& path)
	: CLogReader(path), m_in(path), m_archive(m_in), m_guard(initClassesThenGuard(path))
{
	if (!m_guard->active())
		warn(Problem::Other, "",
			 "could not start the guard process (fork failed): a corrupt object could crash "
			 "this run");
}

std::unique_ptr<CDeserializationGuard> CRawlogReader::initClassesThenGuard(
	const std::string& path)
{
	// Idempotent; guards against a linker that dropped a module's static registration.
	mrpt::obs::registerAllClasses_mrpt_obs();
	mrpt::maps::registerAllClasses_mrpt_maps();
	return std::make_unique<CDeserializationGuard>(path);
}

void CRawlogReader::countContent(const CSerializable& object)
{
	// "mrpt::obs::CObservationBearingRange" -> "CObservationBearingRange", as users name them.
	const std::string name = object.GetRuntimeClass()->className;
	const size_t colons = name.rfind("::");
	++m_stats.contents[colons == std::string::npos ? name : name.substr(colons + 2)];
}

std::string CRawlogReader::placeOf(uint64_t byte) const
{
	return "byte " + std::to_string(byte);
}

CSerializable::Ptr CRawlogReader::readObject(uint64_t start)
{
	// The guard's child meets the object first; a failure there is not repeated here.
	TObjectRead r = m_guard->checkNextObject(start);
	if (m_guard->gaveUp() && !m_guardLossReported)
	{
		m_guardLossReported = true;
		warn(Problem::Other, placeOf(start),
			 "the guard process sent no report for 30 s and was stopped: from here a corrupt "
			 "object could crash this run");
	}
	if (r.result != TObjectRead::Result::Failed) r = readArchiveObject(m_in, m_archive);
	if (r.result == TObjectRead::Result::Failed)
		throw CLogReadError(path(), r.place, r.problem);
	return r.object;  // null at the clean end
}

std::optional<TLogEntry> CRawlogReader::next()
{
	if (m_finished) return std::nullopt;
	try
	{
		CActionCollection::Ptr actions;
		uint64_t actionsAt = 0;
		while (true)
		{
			const uint64_t start = m_in.position();
			const CSerializable::Ptr obj = readObject(start);
			if (!obj)
			{
				m_finished = true;
				// Simulated rawlogs (simul.rawlog, RO-SLAM_demo) end so; MRPT ignores it too.
				// A gzip file cut here fails the trailer check below.
				if (actions)
					warn(Problem::Other, placeOf(actionsAt),
						 "the file ends with this action collection, without the sensory frame "
						 "that would follow it: ignored");
				reportUnlistedWarnings();
				m_in.verifyCompleteAtEnd();
				return std::nullopt;
			}
			if (auto acts = std::dynamic_pointer_cast<CActionCollection>(obj))
			{
				for (const auto& a : *acts)
					if (a.get_ptr()) countContent(*a.get_ptr());
				if (actions)
					warn(Problem::Other, placeOf(actionsAt),
						 "action collection not followed by a sensory frame: dropped");
				actions = acts;
				actionsAt = start;
				continue;
			}
			if (auto frame = std::dynamic_pointer_cast<CSensoryFrame>(obj))
			{
				TLogEntry entry;
				entry.where = path() + ": " + placeOf(actions ? actionsAt : start);
				entry.actions = actions ? actions : CActionCollection::Create();
				for (const auto& a : *entry.actions)
					if (std::dynamic_pointer_cast<mrpt::obs::CActionRobotMovement2D>(
							a.get_ptr()))
						++m_stats.odometry;
				checkFrame(*frame, placeOf(start));
				entry.observations = frame;
				++m_stats.entries;
				return entry;
			}
			if (auto obs = std::dynamic_pointer_cast<CObservation>(obj))
			{
				if (actions)
				{
					warn(Problem::Other, placeOf(actionsAt),
						 "action collection not followed by a sensory frame: dropped");
					actions.reset();
				}
				if (!checkObservation(*obs, placeOf(start))) continue;
				TLogEntry entry;
				entry.where = path() + ": " + placeOf(start);
				entry.observation = obs;
				++m_stats.entries;
				return entry;
			}
			++m_stats.ignoredObjects;
			countContent(*obj);
			warn(Problem::Other, placeOf(start),
				 std::string("object of class ") + obj->GetRuntimeClass()->className +
					 " ignored (neither an observation nor a sensory frame)");
		}
	}
	catch (const CLogReadError&)
	{
		m_finished = true;
		reportUnlistedWarnings();
		throw;
	}
}

bool CRawlogReader::checkObservation(CObservation& obs, const std::string& place)
{
	countContent(obs);
	auto* scan = dynamic_cast<CObservation2DRangeScan*>(&obs);
	if (scan && scan->getScanSize() < 2)
	{
		++m_stats.emptyScans;
		warn(Problem::EmptyScan, place,
			 mrpt::format("scan '%s' with %zu ray(s) skipped", scan->sensorLabel.c_str(),
						  scan->getScanSize()));
		return false;
	}
	if (scan)
	{
		markBadRangesInvalid(*scan, place);
		++m_stats.scans;
	}
	if (dynamic_cast<const mrpt::obs::CObservationOdometry*>(&obs)) ++m_stats.odometry;
	checkTimeOrder(obs.sensorLabel.empty() ? obs.GetRuntimeClass()->className : obs.sensorLabel,
				   obs.timestamp, place, scan != nullptr);
	return true;
}

void CRawlogReader::checkFrame(CSensoryFrame& frame, const std::string& place)
{
	for (auto it = frame.begin(); it != frame.end();)
	{
		if (*it && checkObservation(**it, place))
			++it;
		else
			it = frame.erase(it);
	}
}

}  // namespace lrgc::apps
