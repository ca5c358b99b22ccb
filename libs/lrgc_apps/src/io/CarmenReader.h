/* Streaming reader of CARMEN logs (plain text or gzip): FLASER, RLASER, ROBOTLASER1, ODOM.
 *
 * Lines are read in file order and never sorted: the recorded timestamps (ipc_timestamp,
 * mrpt::Clock::fromDouble) are the identifiers the benchmark relations refer to, and in
 * Intel they jitter backwards 631 times while the file order is the true one.
 * Per laser line: a CObservationOdometry ("ODOMETRY") holding the robot pose of that same
 * line (odom_x odom_y odom_theta), then the CObservation2DRangeScan ("LASER" for FLASER and
 * ROBOTLASER1, "REAR_LASER" for RLASER) with the same timestamp, rightToLeft, its aperture
 * and sensorPose (laser pose of the line relative to the robot pose of the line, rotated by
 * the offset of the beam fan's centre, see TLogReaderOptions), maxRange, and the invalid
 * flag on no-returns, NaN and negative readings. ODOM lines: a CObservationOdometry each,
 * in file order. (Every laser message read here carries its pose, so a scan's odometry never
 * needs interpolating between ODOM lines, which would mix in their timestamp jitter.)
 * A malformed line is skipped with a warning naming its line number; a truncated gzip
 * stream throws CLogReadError at the end, after every complete line was returned.
 */
#pragma once

#include "io/CarmenLine.h"
#include "io/LogInputFile.h"
#include <lrgc_apps/io/LogReader.h>

#include <deque>

namespace lrgc::apps
{
class CCarmenReader final : public CLogReader
{
public:
	CCarmenReader(const std::string& path, const TLogReaderOptions& options);

	std::optional<TLogEntry> next() override;
	double fractionRead() const override { return m_in.fractionRead(); }
	LogFormat format() const override { return LogFormat::Carmen; }

private:
	/** The next line without its end of line; false at the end of the file. */
	bool readLine(std::string& line);
	/** Turns one line into entries appended to m_pending (none if skipped). */
	void processLine(const std::string& line);
	void addLaser(const TCarmenLaser& laser, const std::string& place);
	void addOdometry(const TCarmenOdometry& odom, const std::string& place);

	TLogReaderOptions m_options;
	CLogInputFile m_in;
	std::string m_buffer;  // bytes read but not yet split into lines
	size_t m_bufferPos = 0;
	size_t m_lineNumber = 0;
	bool m_lineEndedFile = false;  // the current line ended with the file, not with '\n'
	TCarmenRecord m_record;        // reused: keeps its range vector's capacity
	std::deque<TLogEntry> m_pending;
	bool m_finished = false;
};

}  // namespace lrgc::apps
