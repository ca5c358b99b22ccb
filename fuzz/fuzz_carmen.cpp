/* Fuzz target: the CARMEN line parser (parseCarmenLine) on every line of the input, then the
 * whole input as a log file through openLog() (format detection and CCarmenReader).
 *
 * Invariants: a Malformed line says why; a laser or odometry line that parses has the number
 * of ranges it declares and a finite pose and timestamp; a ROBOTLASER1 line has a positive
 * resolution and maximum range. The reader throws nothing but CLogReadError, and every scan
 * it returns has at least 2 rays. */
#include "io/CarmenLine.h"
#include <lrgc_apps/io/LogReader.h>

#include <cmath>
#include <string_view>

#include "fuzz_common.h"

using namespace lrgc::apps;
using Kind = TCarmenRecord::Kind;

namespace
{
bool finitePose(const mrpt::math::TPose2D& p)
{
	return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.phi);
}

void checkRecord(const TCarmenRecord& r)
{
	if (r.kind == Kind::Malformed)
	{
		LRGC_FUZZ_CHECK(!r.problem.empty(), "a malformed line says why");
		return;
	}
	LRGC_FUZZ_CHECK(r.problem.empty(), "a line that parses has no problem");
	LRGC_FUZZ_CHECK(r.fieldsAfterTimestamp <= 2, "at most hostname and logger_timestamp");
	if (r.kind == Kind::Odometry)
	{
		LRGC_FUZZ_CHECK(finitePose(r.odometry.pose), "odometry pose finite");
		LRGC_FUZZ_CHECK(std::isfinite(r.odometry.timestamp), "odometry timestamp finite");
	}
	if (r.kind == Kind::FrontLaser || r.kind == Kind::RearLaser || r.kind == Kind::RobotLaser)
	{
		LRGC_FUZZ_CHECK(finitePose(r.laser.laserPose) && finitePose(r.laser.robotPose),
						"laser poses finite");
		LRGC_FUZZ_CHECK(std::isfinite(r.laser.timestamp), "laser timestamp finite");
		LRGC_FUZZ_CHECK(r.laser.hasOwnGeometry == (r.kind == Kind::RobotLaser),
						"only ROBOTLASER1 has its own geometry");
		if (r.kind == Kind::RobotLaser)
			LRGC_FUZZ_CHECK(r.laser.angularResolution > 0 && r.laser.maxRange > 0 &&
								std::isfinite(r.laser.startAngle),
							"ROBOTLASER1 geometry valid");
	}
	if (r.kind == Kind::Ignored)
		LRGC_FUZZ_CHECK(r.message != "FLASER" && r.message != "RLASER" &&
							r.message != "ROBOTLASER1" && r.message != "ODOM",
						"a known message is never ignored");
}

void readWholeLog(const std::string& path)
{
	try
	{
		const auto reader = openLog(path);
		while (const auto entry = reader->next())
		{
			LRGC_FUZZ_CHECK(bool(entry->observation) != bool(entry->observations),
							"an entry holds one observation or one sensory frame");
			if (const auto* scan = dynamic_cast<const mrpt::obs::CObservation2DRangeScan*>(
					entry->observation.get()))
				LRGC_FUZZ_CHECK(scan->getScanSize() >= 2, "scans have 2 rays or more");
			reader->takeWarnings();
			const double f = reader->fractionRead();
			LRGC_FUZZ_CHECK(f >= 0 && f <= 1, "fraction read in [0, 1]");
		}
		reader->takeWarnings();
	}
	catch (const CLogReadError&)
	{
	}
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	const std::string_view text(reinterpret_cast<const char*>(data), size);
	TCarmenRecord rec;
	for (size_t start = 0; start <= text.size();)
	{
		size_t end = text.find('\n', start);
		if (end == std::string_view::npos) end = text.size();
		parseCarmenLine(text.substr(start, end - start), rec);
		checkRecord(rec);
		start = end + 1;
	}
	readWholeLog(lrgc::fuzz::writeScratch("carmen.clf", data, size));
	return 0;
}
