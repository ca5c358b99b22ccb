/* How long CMetricMapBuilderLRGC::getCurrentlyBuiltMetricMap() takes on a large map: the
 * first call (the grid of every keyframe), a call with nothing changed, and a call after each
 * of the next keyframes (what a viewer polling the map pays after every keyframe); and what
 * a live save costs the mapping thread (the snapshot, snapshotRunOutputs) on that map.
 *
 * It maps LOG but the last HOLD scans through the public map-builder interface (as the app
 * does, default parameters), then times the calls while feeding the held-back scans. Only the
 * public interface is used, so the same program measures any version of the builder. Prints
 * a table; asserts nothing (bench/, not a test).
 *
 * Run: build/bin/metric_map_timing ../shared/datasets/intel/intel.clf.gz [HOLD=400]
 * [KEYFRAMES=20]
 */
#include <lrgc/map_builder/CMetricMapBuilderLRGC.h>
#include <lrgc_apps/RunOutputs.h>
#include <lrgc_apps/io/LogReader.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace
{
using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0)
{
	return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/** Times one getCurrentlyBuiltMetricMap() call [ms]; touches the grid it returns. */
double timeMetricMap(const lrgc::CMetricMapBuilderLRGC& builder, size_t* cells)
{
	const auto t0 = Clock::now();
	const mrpt::maps::CMultiMetricMap* map = builder.getCurrentlyBuiltMetricMap();
	const double ms = msSince(t0);
	const auto grid = map->mapByClass<mrpt::maps::COccupancyGridMap2D>();
	*cells = grid ? size_t(grid->getSizeX()) * grid->getSizeY() : 0;
	return ms;
}

bool isScan(const lrgc::apps::TLogEntry& e)
{
	if (e.observation)
		return std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(e.observation) !=
			   nullptr;
	return e.observations &&
		   e.observations->getObservationByClass<mrpt::obs::CObservation2DRangeScan>() !=
			   nullptr;
}
}  // namespace

int main(int argc, char** argv)
{
	if (argc < 2)
	{
		std::fprintf(stderr, "usage: %s LOG [HOLD_SCANS=400] [KEYFRAMES=20]\n", argv[0]);
		return 2;
	}
	const size_t hold = argc > 2 ? std::strtoul(argv[2], nullptr, 10) : 400;
	const size_t keyframesToTime = argc > 3 ? std::strtoul(argv[3], nullptr, 10) : 20;

	std::vector<lrgc::apps::TLogEntry> entries;
	size_t scans = 0;
	{
		const auto reader = lrgc::apps::openLog(argv[1]);
		while (auto e = reader->next())
		{
			scans += isScan(*e);
			entries.push_back(std::move(*e));
		}
	}
	lrgc::CMetricMapBuilderLRGC builder;
	builder.logging_enable_console_output = false;
	size_t next = 0, fed = 0;
	const auto t0 = Clock::now();
	for (; next < entries.size() && fed + hold < scans; ++next)
	{
		fed += isScan(entries[next]);
		lrgc::apps::feedEntry(builder, entries[next]);
	}
	std::printf(
		"%s: mapped %zu of %zu scans in %.1f s: %zu keyframes, %zu loop-closure links\n",
		argv[1], fed, scans, msSince(t0) / 1e3, builder.keyframes().size(),
		builder.stats().loopClosureLinks);

	size_t cells = 0;
	const double first = timeMetricMap(builder, &cells);
	const double again = timeMetricMap(builder, &cells);
	std::printf(
		"getCurrentlyBuiltMetricMap: first call %.2f ms (%zu cells), again with nothing "
		"changed %.3f ms\n",
		first, cells, again);

	const auto s0 = Clock::now();
	const auto snapshot = lrgc::apps::snapshotRunOutputs(builder, {});
	std::printf("snapshot of the outputs for a live save: %.2f ms (%zu scans, %zu keyframes)\n",
				msSince(s0), snapshot.trajectory.size(), snapshot.gridKeyframes.size());

	std::vector<double> afterKeyframe;
	size_t afterLoopResult = 0;
	while (afterKeyframe.size() < keyframesToTime && next < entries.size())
	{
		const size_t keyframes = builder.keyframes().size();
		const size_t loopLinks = builder.stats().loopClosureLinks;
		while (next < entries.size() && builder.keyframes().size() == keyframes)
			lrgc::apps::feedEntry(builder, entries[next++]);
		if (builder.keyframes().size() == keyframes) break;
		afterLoopResult += builder.stats().loopClosureLinks != loopLinks;
		afterKeyframe.push_back(timeMetricMap(builder, &cells));
	}
	if (afterKeyframe.empty()) return 0;
	std::vector<double> sorted = afterKeyframe;
	std::sort(sorted.begin(), sorted.end());
	std::printf(
		"after one more keyframe (%zu times, %zu of them with new loop-closure links): "
		"median %.2f ms, max %.2f ms; each:",
		sorted.size(), afterLoopResult, sorted[sorted.size() / 2], sorted.back());
	for (const double ms : afterKeyframe) std::printf(" %.2f", ms);
	std::printf("\n");
	return 0;
}
