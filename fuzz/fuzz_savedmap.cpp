/* Fuzz target: a saved map's map.simplemap.gz as --initial-map / --localize read it
 * (readSimplemapFile, what loadSavedMap reads a map file with: CLogInputFile, the
 * deserialization guard's child under its memory budget, MRPT's CSimpleMap deserializer).
 *
 * Invariants: it throws nothing but std::runtime_error (one line naming the file), and a map
 * it accepts holds at least one keyframe. */
#include <lrgc_apps/io/SimplemapFile.h>

#include <string>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	const std::string& path = lrgc::fuzz::writeScratch("map.simplemap.gz", data, size);
	try
	{
		const auto map = lrgc::apps::readSimplemapFile(path, "--localize");
		LRGC_FUZZ_CHECK(!map.empty(), "an accepted map has keyframes");
	}
	catch (const std::runtime_error& e)
	{
		LRGC_FUZZ_CHECK(std::string(e.what()).find('\n') == std::string::npos,
						"the error is one line");
	}
	return 0;
}
