/* Test-only access to the loop-closing worker: a slow worker on purpose, to test that the
 * mapping thread waits for results where the schedule says and never otherwise. Not
 * installed (libs/lrgc/CMakeLists.txt): users of the library have no such hook. */
#pragma once

#include <chrono>

namespace lrgc
{
class CLoopClosing;
class CMetricMapBuilderLRGC;

struct TLoopClosingTestAccess
{
	/** Every loop search of `builder` first sleeps `d`; kept across initialize(). */
	static void setExtraDelay(CMetricMapBuilderLRGC& builder, std::chrono::milliseconds d);
	/** Every loop search of `loops` first sleeps `d`. */
	static void setExtraDelay(CLoopClosing& loops, std::chrono::milliseconds d);
};

}  // namespace lrgc
