/* The map builder's grid (getCurrentlyBuiltMetricMap, kept by CIncrementalGrid) on real logs:
 * after every keyframe it must be, cell for cell, the grid built from scratch from the
 * keyframes' current poses, through local window moves, loop closures and the final
 * optimisation. SENA (one loop) at every keyframe; Intel (many loop closures) every 10th
 * keyframe of its first 4000 scans. */
#include <gtest/gtest.h>
#include <lrgc/map_builder/CMetricMapBuilderLRGC.h>
#include <lrgc/map_builder/IncrementalGrid.h>
#include <lrgc_apps/io/LogReader.h>

#include "test_data.h"

#include <memory>

namespace
{
using lrgc::CIncrementalGrid;
using Update = CIncrementalGrid::Update;

size_t differingCells(const mrpt::maps::COccupancyGridMap2D& a,
					  const mrpt::maps::COccupancyGridMap2D& b)
{
	if (a.getSizeX() != b.getSizeX() || a.getSizeY() != b.getSizeY() ||
		a.getXMin() != b.getXMin() || a.getYMin() != b.getYMin())
		return std::max(a.getRawMap().size(), b.getRawMap().size());
	size_t n = 0;
	for (size_t i = 0; i < a.getRawMap().size(); ++i) n += a.getRawMap()[i] != b.getRawMap()[i];
	return n;
}

/** The builder's grid against a fresh build; also feeds `mirror` (a CIncrementalGrid of the
 * same keyframes) to count the kinds of update the builder's own grid went through. */
void expectGridIsFresh(const lrgc::CMetricMapBuilderLRGC& builder, CIncrementalGrid& mirror,
					   const std::string& where)
{
	const auto* map = builder.getCurrentlyBuiltMetricMap();
	const auto grid = map->mapByClass<mrpt::maps::COccupancyGridMap2D>();
	ASSERT_TRUE(grid);
	const auto keyframes = builder.gridKeyframes();
	const auto fresh = CIncrementalGrid::buildFromScratch(keyframes, builder.gridSettings());
	ASSERT_EQ(differingCells(*grid, *fresh), 0u)
		<< where << ", " << keyframes.size() << " keyframes";
	mirror.update(keyframes);
}

/** `mirror` gets the builder's grid settings (its tail covers the builder's window). */
void mapAndCompare(const std::string& log, size_t maxScans, size_t everyKeyframes,
				   std::unique_ptr<CIncrementalGrid>& mirror, size_t* loopLinks)
{
	lrgc::CMetricMapBuilderLRGC builder;
	builder.logging_enable_console_output = false;
	mirror = std::make_unique<CIncrementalGrid>(builder.gridSettings());
	const auto reader = lrgc::apps::openLog(log);
	size_t lastChecked = 0;
	while (auto e = reader->next())
	{
		lrgc::apps::feedEntry(builder, *e);
		const size_t n = builder.keyframes().size();
		if (n >= lastChecked + everyKeyframes)
		{
			lastChecked = n;
			expectGridIsFresh(builder, *mirror, log + " " + e->where);
			if (::testing::Test::HasFatalFailure()) return;
		}
		if (builder.stats().scans >= maxScans) break;
	}
	builder.finish();  // the final optimisation moves everything
	expectGridIsFresh(builder, *mirror, log + ", after finish()");
	*loopLinks = builder.stats().loopClosureLinks;
}
}  // namespace

TEST(IncrementalGridOnRealLogs, SenaEveryKeyframeEqualsAFreshBuild)
{
	LRGC_SKIP_IF_MISSING(lrgc::test::senaRawlogPath());
	std::unique_ptr<CIncrementalGrid> mirror;
	size_t loopLinks = 0;
	mapAndCompare(lrgc::test::senaRawlogPath(), SIZE_MAX, 1, mirror, &loopLinks);
	EXPECT_GT(loopLinks, 0u) << "the loop of SENA should close";
	// The window moves its keyframes at each keyframe; the cheap path is the usual one.
	EXPECT_GT(mirror->count(Update::TailReinserted), 50u);
	EXPECT_GT(mirror->count(Update::Rebuilt), 0u);
}

TEST(IncrementalGridOnRealLogs, IntelEqualsAFreshBuildThroughLoopClosures)
{
	const std::string intel = lrgc::test::sharedDatasetPath("intel/intel.clf.gz");
	LRGC_SKIP_IF_MISSING(intel);
	std::unique_ptr<CIncrementalGrid> mirror;
	size_t loopLinks = 0;
	mapAndCompare(intel, 4000, 10, mirror, &loopLinks);
	EXPECT_GT(loopLinks, 10u);
	GTEST_LOG_(INFO) << "updates: appended " << mirror->count(Update::Appended)
					 << ", tail re-inserted " << mirror->count(Update::TailReinserted)
					 << ", rebuilt " << mirror->count(Update::Rebuilt);
}
