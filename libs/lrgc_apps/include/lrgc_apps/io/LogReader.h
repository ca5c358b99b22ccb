/* Log readers of lrgc-slam: MRPT rawlogs (both layouts) and CARMEN logs, streamed.
 *
 * openLog() detects the format from the content (gzip or not, then an MRPT archive object
 * header or CARMEN text keywords), never from the name alone, and returns a reader that
 * yields one TLogEntry at a time in file order: memory does not grow with the file.
 *
 * Errors. A problem the run can go past (a malformed CARMEN line, NaN or negative ranges,
 * an empty scan, time going backwards) is skipped or repaired and reported by
 * takeWarnings(), each message naming the file and the place. Recurring kinds are listed
 * verbatim a few times, then counted, and the count is reported at the end of the file.
 * A problem the run cannot go past (missing file, truncated or corrupt rawlog, truncated or
 * damaged gzip stream, an object that crashes MRPT's deserializer: see RawlogObjects.h)
 * throws CLogReadError from next(), after every complete entry before the damage has been
 * returned, so the caller can save what it built and exit non-zero. Nothing else is thrown
 * for bad input.
 *
 * Places: "<file>: line N" (1-based) for CARMEN, "<file>: byte N" for rawlogs, N being the
 * offset of the object in the uncompressed archive (= the file offset for a plain file).
 */
#pragma once

#include <lrgc_apps/io/RawlogConversion.h>
#include <lrgc_apps/io/LogReaderOptions.h>
#include <mrpt/core/Clock.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <array>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace lrgc::apps
{
/** One item of a log, in file order. Exactly one of `observations` / `observation` is set. */
struct TLogEntry
{
	/** Rawlog layout 1 only: the odometry increments before `observations`. Empty, never
	 * null, for a sensory frame with no action collection before it: SENA and simul.rawlog
	 * start so, and MRPT's own loop (rawlog-edit, icp-slam) skips that first frame, so it
	 * counts one scan less (SENA: 224 of 225). */
	mrpt::obs::CActionCollection::Ptr actions;
	/** Rawlog layout 1 only. */
	mrpt::obs::CSensoryFrame::Ptr observations;
	/** Rawlog layout 2 and CARMEN: one observation. A CARMEN laser line yields a
	 * CObservationOdometry ("ODOMETRY") and then a CObservation2DRangeScan ("LASER" or
	 * "REAR_LASER") with the same timestamp; an ODOM line one CObservationOdometry. */
	mrpt::obs::CObservation::Ptr observation;
	/** "<file>: byte N" or "<file>: line N". */
	std::string where;
};

/** Hands an entry to anything with MRPT's map-builder intake (CMetricMapBuilderLRGC,
 * CLocalizer, ...): a sensory frame with its actions (an empty collection when none came
 * before it) or a lone observation. */
template <class Consumer>
void feedEntry(Consumer& consumer, TLogEntry& e)
{
	if (e.observations)
	{
		mrpt::obs::CActionCollection noActions;
		consumer.processActionObservation(e.actions ? *e.actions : noActions, *e.observations);
	}
	else if (e.observation)
		consumer.processObservation(e.observation);
}

enum class LogFormat
{
	MrptRawlog,
	Carmen
};

/** Counts since the reader was opened. */
struct TLogReadStats
{
	size_t entries = 0;         //!< TLogEntry returned
	size_t scans = 0;           //!< 2D range scans returned
	size_t odometry = 0;        //!< CObservationOdometry and CActionRobotMovement2D returned
	size_t skippedLines = 0;    //!< malformed CARMEN lines skipped
	size_t ignoredLines = 0;    //!< comments, blank lines, CARMEN messages not read (PARAM...)
	size_t ignoredObjects = 0;  //!< rawlog objects that are neither observation nor frame
	size_t emptyScans = 0;      //!< scans with fewer than 2 readings, skipped
	size_t invalidRanges = 0;   //!< NaN or negative readings marked invalid
	size_t noReturnRanges = 0;  //!< CARMEN readings at max range or +inf marked invalid
	size_t scanTimeJumpsBack = 0;    //!< a scan older than the previous one of its sensor
	size_t otherTimeJumpsBack = 0;   //!< the same for odometry and other observations
	double largestTimeJumpBack = 0;  //!< [s]
	size_t warnings = 0;             //!< recoverable problems met, listed or only counted
	/** What the file holds, to say so when it holds nothing to map. Rawlog: objects per MRPT
	 * class (observations in and out of sensory frames, actions, other objects). CARMEN:
	 * lines per message ("FLASER lines", "malformed FLASER lines", "PARAM lines"). */
	std::map<std::string, size_t> contents;
};

/** A read error the run cannot go past; what() is "<file>: <place>: <problem>". */
class CLogReadError : public std::runtime_error
{
public:
	CLogReadError(const std::string& file, const std::string& place,
				  const std::string& problem);
	const std::string& file() const { return m_file; }
	/** "byte N", "line N", or "" when the problem concerns the whole file. */
	const std::string& place() const { return m_place; }

private:
	std::string m_file, m_place;
};

class CLogReader
{
public:
	virtual ~CLogReader();
	CLogReader(const CLogReader&) = delete;
	CLogReader& operator=(const CLogReader&) = delete;

	/** The next entry in file order, nullopt at the end. Throws CLogReadError when it
	 * cannot go on, after having returned every complete entry before the damage. */
	virtual std::optional<TLogEntry> next() = 0;
	/** Fraction of the file read, in [0, 1], for a progress bar. */
	virtual double fractionRead() const = 0;
	virtual LogFormat format() const = 0;

	const std::string& path() const { return m_path; }
	/** Recoverable problems since the last call, each naming file and place. */
	std::vector<std::string> takeWarnings();
	const TLogReadStats& stats() const { return m_stats; }

protected:
	explicit CLogReader(std::string path);

	enum class Problem
	{
		MalformedLine,
		BadRanges,
		EmptyScan,
		TimeBackwards,
		Other,
		Count
	};
	/** Records "<file>: <place>: <what>"; past kListedPerProblem of a kind, only counts. */
	void warn(Problem kind, const std::string& place, const std::string& what);
	/** Checks that `t` is not older than the previous time of `stream`; warns if it is. */
	void checkTimeOrder(const std::string& stream, mrpt::Clock::time_point t,
						const std::string& place, bool isScan);
	/** Marks NaN, infinite and negative readings of valid rays invalid; returns their count. */
	size_t markBadRangesInvalid(mrpt::obs::CObservation2DRangeScan& scan,
								const std::string& place);
	/** At the end of the file: a warning per kind with the count of those not listed. */
	void reportUnlistedWarnings();

	TLogReadStats m_stats;
	static constexpr size_t kListedPerProblem = 5;

private:
	struct TStreamTime
	{
		mrpt::Clock::time_point time;
		std::string place;
	};
	std::string m_path;
	std::vector<std::string> m_warnings;
	std::array<size_t, static_cast<size_t>(Problem::Count)> m_problemCounts{};
	std::map<std::string, TStreamTime> m_lastTimes;
};

/** By content: gzip magic, then an MRPT archive object header or CARMEN text messages.
 * Throws CLogReadError for a missing, unreadable, empty or unrecognised file. */
LogFormat detectLogFormat(const std::string& path);

/** Opens `path` with the reader of its detected format. Throws CLogReadError. */
std::unique_ptr<CLogReader> openLog(const std::string& path, const TLogReaderOptions& = {});

}  // namespace lrgc::apps
