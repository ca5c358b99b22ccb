/* lrgc-slam --merge MAP_A MAP_B --out DIR: two saved maps made one (MergeMaps.h). */
#include "AppConfig.h"
#include "ErrorText.h"
#include "MergeMaps.h"
#include "Progress.h"
#include "RunConfigFile.h"
#include "SlamApp.h"
#include "StopSignalWatcher.h"
#include "lrgc_apps/RunOutputs.h"
#include "lrgc_apps/RunStats.h"
#include "lrgc_apps/SavedMap.h"

#include <lrgc/common/CpuTime.h>
#include <lrgc/map_builder/CMetricMapBuilderLRGC.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/core/format.h>

namespace lrgc::apps
{
namespace
{
struct TMergeInputs
{
	TSavedMap a, b;
	TTrajectory bScans;  //!< MAP_B's trajectory.tum, if it has one
};

// Both maps and B's trajectory, or a one-line error naming the file (thrown).
TMergeInputs loadMergeInputs(const TSlamCommandLine& cl)
{
	TMergeInputs in{loadSavedMap(cl.mergeA, "--merge"), loadSavedMap(cl.mergeB, "--merge"), {}};
	in.bScans = savedMapTrajectory(in.b);
	return in;
}

std::string mergingMessage(const TMergeInputs& in, const CMetricMapBuilderLRGC& builder)
{
	return mrpt::format(
		"merging '%s' (%zu keyframes) into '%s' (%zu keyframes): its keyframes are replayed "
		"as a piece until global correlation places them in that map's frame",
		in.b.path.c_str(), in.b.keyframes.size(), in.a.path.c_str(),
		builder.graph().numNodes());
}

std::string noOverlapMessage(const TSlamCommandLine& cl, const TRunSummary& run)
{
	return mrpt::format(
		"the maps '%s' and '%s' do not overlap: global correlation placed none of the %zu "
		"keyframes of the second in the first (%zu attempts, last: %s); nothing written to %s",
		cl.mergeA.c_str(), cl.mergeB.c_str(), run.mergedMapKeyframes, run.startAttempts,
		run.lastJoinRejection.empty() ? "none" : run.lastJoinRejection.c_str(),
		cl.outDir.c_str());
}
}  // namespace

int CSlamApp::runMerge(const TSlamCommandLine& cl)
{
	const TAppConfig cfg = loadAppConfig(cl);
	for (const auto& w : cfg.warnings) report("warning: " + w);  // old key names, all shown
	const CStopSignalWatcher signals;  // before the optimiser's threads, which inherit its mask
	CMetricMapBuilderLRGC builder(cfg.lrgc);
	builder.logging_enable_console_output = false;  // warnings are reported below
	builder.setStopToken(signals.token());
	std::optional<TMergeInputs> in;
	try
	{
		in = loadMergeInputs(cl);
		for (const auto* m : {&in->a, &in->b})
			for (const auto& w : m->warnings) report("warning: " + w);
		initializeFromSavedMap(builder, in->a);
	}
	catch (const std::exception& e)
	{
		reportError(e);
		return kExitInputError;
	}
	report("lrgc-slam: " + mergingMessage(*in, builder));
	CKeyframeReplay replay(in->b);
	CProgress progress(m_err, cl.quiet, cl.progressInterval);
	CRunClock clock;
	TRunSummary run;
	run.input = in->b.path;
	run.format = "simplemap";
	run.configIni = runConfigText(cfg, in->b.path);
	run.mergedMap = in->b.path;
	run.mergedMapKeyframes = in->b.keyframes.size();
	run.stages.startMapping();
	const double threadCpu0 = threadCpuSeconds();
	int exitCode =
		continueInitialMap(in->a, cfg, replay, builder, progress, run, signals, true);
	exitCode = endOffline(builder, replay, progress, run, threadCpu0, exitCode);
	if (!run.joined)
	{
		reportError(exitCode == kExitOk ? noOverlapMessage(cl, run)
										: run.status + "; nothing written to " + cl.outDir);
		return exitCode == kExitOk ? kExitInputError : exitCode;
	}
	finishRunSummary(run, clock, m_warningsTotal);
	TRunOutputsSnapshot outputs = snapshotRunOutputs(builder, run);
	outputs.trajectory =
		rehangTrajectory(in->bScans, replay.keyframePoses(), builder.trajectory());
	writeRunOutputs(outputs, *builder.buildOccupancyGrid(), cl.outDir);
	reportEnd(cl, builder, run, exitCode);
	return exitCode;
}

}  // namespace lrgc::apps
