/* Fuzz target: CRawlogReader on the input as a rawlog file (plain or gzip), with its guard
 * process (RawlogObjects.h) meeting every object first, as in lrgc-slam.
 *
 * MRPT's deserializers (not instrumented here) crash or allocate without bound on corrupt
 * objects; the guard's child meets them first and dies or fails in the parent's stead, which
 * the reader turns into CLogReadError. So the invariants are: this process never crashes,
 * the reader throws nothing but CLogReadError, every entry holds exactly one of observation /
 * sensory frame, and the returned scans have at least 2 rays and no NaN/negative valid ray. */
#include "io/RawlogReader.h"

#include <cmath>

#include "fuzz_common.h"

using namespace lrgc::apps;

namespace
{
void checkScan(const mrpt::obs::CObservation& obs)
{
	const auto* scan = dynamic_cast<const mrpt::obs::CObservation2DRangeScan*>(&obs);
	if (!scan) return;
	LRGC_FUZZ_CHECK(scan->getScanSize() >= 2, "scans have 2 rays or more");
	for (size_t i = 0; i < scan->getScanSize(); ++i)
		if (scan->getScanRangeValidity(i))
			LRGC_FUZZ_CHECK(std::isfinite(scan->getScanRange(i)) && scan->getScanRange(i) >= 0,
							"a valid ray has a finite range >= 0");
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	const std::string& path = lrgc::fuzz::writeScratch("input.rawlog", data, size);
	try
	{
		CRawlogReader reader(path);
		while (const auto entry = reader.next())
		{
			LRGC_FUZZ_CHECK(bool(entry->observation) != bool(entry->observations),
							"an entry holds one observation or one sensory frame");
			LRGC_FUZZ_CHECK(!entry->observations || entry->actions,
							"a sensory frame comes with an action collection (maybe empty)");
			if (entry->observation) checkScan(*entry->observation);
			if (entry->observations)
				for (const auto& obs : *entry->observations)
				{
					LRGC_FUZZ_CHECK(obs != nullptr, "no null observation in a frame");
					checkScan(*obs);
				}
			reader.takeWarnings();
		}
		reader.takeWarnings();
	}
	catch (const CLogReadError&)
	{
	}
	return 0;
}
