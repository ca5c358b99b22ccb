#include <lrgc/map_builder/TestAccess.h>

#include <lrgc/loop_closing/LoopClosing.h>
#include <lrgc/loop_closing/LoopClosingWorker.h>
#include <lrgc/map_builder/CMetricMapBuilderLRGC.h>

namespace lrgc
{
void TLoopClosingTestAccess::setExtraDelay(CMetricMapBuilderLRGC& builder,
										   std::chrono::milliseconds d)
{
	builder.m_loopSearchExtraDelay = d;
	if (builder.m_loops) setExtraDelay(*builder.m_loops, d);
}

void TLoopClosingTestAccess::setExtraDelay(CLoopClosing& loops, std::chrono::milliseconds d)
{
	loops.m_worker->m_extraDelayMs = d.count();
}

}  // namespace lrgc
