#include "lrgc_apps/io/RawlogConversion.h"

#include "atomic_file.h"
#include "lrgc_apps/io/LogReader.h"

#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/datetime.h>

namespace lrgc::apps
{
namespace
{
// Writes the observations of one entry; layout-1 increments become absolute odometry.
class CObservationWriter
{
public:
	CObservationWriter(mrpt::serialization::CArchive& out, TConversionStats& stats)
		: m_out(out), m_stats(stats)
	{
	}

	void write(const TLogEntry& e)
	{
		if (e.actions) writeIncrements(*e.actions, e.observations);
		if (e.observations)
			for (const auto& obs : *e.observations)
				if (obs) write(*obs);
		if (e.observation) write(*e.observation);
	}

private:
	void write(const mrpt::obs::CObservation& obs)
	{
		m_out << obs;
		++m_stats.observations;
		if (dynamic_cast<const mrpt::obs::CObservation2DRangeScan*>(&obs)) ++m_stats.scans;
		if (dynamic_cast<const mrpt::obs::CObservationOdometry*>(&obs)) ++m_stats.odometry;
	}

	// odometry_k = odometry_{k-1} (+) mean(increment_k), stamped with the increment's time
	// (or, if it has none, that of the frame's first observation).
	void writeIncrements(const mrpt::obs::CActionCollection& actions,
						 const mrpt::obs::CSensoryFrame::Ptr& frame)
	{
		for (const auto& a : actions)
		{
			const auto move =
				std::dynamic_pointer_cast<mrpt::obs::CActionRobotMovement2D>(a.get_ptr());
			if (!move || !move->poseChange.get_ptr()) continue;
			m_odometry = m_odometry + move->poseChange->getMeanVal();
			auto odo = mrpt::obs::CObservationOdometry::Create();
			odo->sensorLabel = "ODOMETRY";
			odo->odometry = m_odometry;
			odo->timestamp = move->timestamp;
			if (odo->timestamp == INVALID_TIMESTAMP && frame && frame->size() > 0)
				odo->timestamp = frame->getObservationByIndex(0)->timestamp;
			write(*odo);
		}
	}

	mrpt::serialization::CArchive& m_out;
	TConversionStats& m_stats;
	mrpt::poses::CPose2D m_odometry;
};
}  // namespace

TConversionStats convertToRawlog(const std::string& inPath, const std::string& outRawlogPath,
								 const TLogReaderOptions& options)
{
	const std::unique_ptr<CLogReader> reader = openLog(inPath, options);
	TConversionStats stats;
	writeArchiveAtomically(outRawlogPath, TFileCompression::Gzip,
						   [&](mrpt::serialization::CArchive& out)
						   {
							   CObservationWriter writer(out, stats);
							   while (const std::optional<TLogEntry> entry = reader->next())
							   {
								   writer.write(*entry);
								   for (auto& w : reader->takeWarnings())
									   stats.warningText.push_back(std::move(w));
							   }
							   for (auto& w : reader->takeWarnings())
								   stats.warningText.push_back(std::move(w));
						   });
	stats.warnings = reader->stats().warnings;
	return stats;
}

}  // namespace lrgc::apps
