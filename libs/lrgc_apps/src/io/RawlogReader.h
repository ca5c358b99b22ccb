/* Streaming reader of MRPT rawlogs, both layouts, plain or gzip-compressed.
 *
 * Objects are read one at a time from the archive (mrpt::serialization::CArchive over a
 * CLogInputFile). Layout 1 pairs each CActionCollection with the CSensoryFrame that follows;
 * layout 2 yields each CObservation. This does what
 * CRawlog::getActionObservationPairOrObservation does, but that function returns false for end
 * of file, truncation and corruption alike (printing to stderr): here a clean end (no byte of a
 * next object) ends the log, while an object cut short or undecodable throws CLogReadError
 * naming its first byte, after every complete entry before it was returned. A gzip rawlog is
 * also checked against its trailer (see CLogInputFile), so a gzip file cut at an object
 * boundary is an error too; a plain one cut there cannot be told from a shorter log. Each
 * object passes the guard of RawlogObjects.h first, so corrupt data that crashes MRPT's
 * deserializer is an error too. A sensory frame with no action collection before it comes with
 * an empty collection; a final action collection with no frame after it (simul.rawlog ends so)
 * is a warning. Scans are checked as CARMEN ones are: NaN/inf/negative ranges marked invalid,
 * scans with fewer than 2 rays dropped, time going backwards per sensor label reported.
 */
#pragma once

#include "io/LogInputFile.h"
#include <lrgc_apps/io/LogReader.h>
#include "io/RawlogObjects.h"

#include <memory>

namespace lrgc::apps
{
class CRawlogReader final : public CLogReader
{
public:
	/** Opens `path`; throws CLogReadError if it cannot be opened. Registers MRPT's classes. */
	explicit CRawlogReader(const std::string& path);

	std::optional<TLogEntry> next() override;
	double fractionRead() const override { return m_in.fractionRead(); }
	LogFormat format() const override { return LogFormat::MrptRawlog; }

private:
	/** The next object, or nullptr at a clean end of file. */
	mrpt::serialization::CSerializable::Ptr readObject(uint64_t start);
	/** Drops empty scans, repairs bad ranges, checks time; false if nothing is left. */
	bool checkObservation(mrpt::obs::CObservation& obs, const std::string& place);
	void checkFrame(mrpt::obs::CSensoryFrame& frame, const std::string& place);
	std::string placeOf(uint64_t byte) const;
	/** Counts `object` in TLogReadStats::contents under its class name. */
	void countContent(const mrpt::serialization::CSerializable& object);

	static std::unique_ptr<CDeserializationGuard> initClassesThenGuard(const std::string& path);

	CLogInputFile m_in;
	TArchive m_archive;
	std::unique_ptr<CDeserializationGuard> m_guard;
	bool m_finished = false;
	bool m_guardLossReported = false;
};

}  // namespace lrgc::apps
