/* stats.json: what a run mapped, how its loops were closed, where its time went and its
 * latencies, as one JSON object (statsJson, RunOutputs.h); the keys are documented
 * where each group is written. */
#include "lrgc_apps/RunOutputs.h"

#include "lrgc_apps/RunStats.h"

#include <mrpt/core/bits_math.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace lrgc::apps
{
std::string jsonString(const std::string& s)
{
	std::string out = "\"";
	for (const char ch : s)
	{
		if (ch == '"' || ch == '\\')
			out += '\\', out += ch;
		else if (static_cast<unsigned char>(ch) < 0x20)
		{
			char buf[8];
			std::snprintf(buf, sizeof(buf), "\\u%04x", ch);
			out += buf;
		}
		else
			out += ch;
	}
	return out + "\"";
}

namespace
{
std::string jsonCounts(const std::map<std::string, size_t>& counts)
{
	std::string out = "{";
	for (const auto& [name, n] : counts)
		out += (out.size() > 1 ? ", " : "") + jsonString(name) + ": " + std::to_string(n);
	return out + "}";
}

// "links", "loop_links" and "loop_closures" of stats.json. Links added to the pose graph, by
// type: "loop" counts every link of type LoopClosure (what lrgc-plot draws from graph.lrgc):
// one per loop closure, the links re-matched after it, the links of keyframes reused at a
// mapped place, and the end-of-run revisit links ("loop_links"). Loop closures: accepted
// matches of a new keyframe with the old map, the number the console prints; a robot driving
// along an old path closes the loop again at each keyframe, so one loop gives several.
std::string loopCountsJson(const TMapBuilderStats& s)
{
	const size_t rematchOrReuse =
		s.loopClosureLinks - std::min(s.loopClosureLinks, s.loopClosures + s.revisitLinks);
	return "  \"links\": {\"odometry\": " + std::to_string(s.odometryLinks) +
		   ", \"scan_match\": " + std::to_string(s.scanMatchLinks) +
		   ", \"loop\": " + std::to_string(s.loopClosureLinks) + "},\n" +
		   "  \"loop_links\": {\"closure\": " + std::to_string(s.loopClosures) +
		   ", \"revisit\": " + std::to_string(s.revisitLinks) +
		   ", \"rematch_or_reuse\": " + std::to_string(rematchOrReuse) +
		   ", \"rejected_at_end\": " + std::to_string(s.finalRejectedLinks) + "},\n" +
		   "  \"loop_closures\": " + std::to_string(s.loopClosures) + ",\n";
}

// [a, b, c] of whole numbers.
std::string jsonList(const std::vector<size_t>& values)
{
	std::string out = "[";
	for (size_t i = 0; i < values.size(); ++i)
		out += (i ? ", " : "") + std::to_string(values[i]);
	return out + "]";
}

// The mapped laser ([MapBuilder] laser_label / --laser, else the first seen) and the scans of
// the other lasers, ignored, per sensor label.
std::string laserJson(const CLaserSelector& lasers)
{
	std::ostringstream j;
	j << "  \"laser\": {\"label\": " << jsonString(lasers.label())
	  << ", \"chosen\": " << (lasers.chosen() ? "true" : "false")
	  << ", \"ignored_scans\": " << jsonCounts(lasers.ignoredScans())
	  << ", \"range_limited_readings\": " << lasers.rangeLimitedReadings() << "},\n";
	return j.str();
}

// The places of the loop searches dropped: [{"keyframe": k, "x": m, "y": m, "phi_deg": deg}].
std::string droppedSearchesJson(const std::vector<size_t>& keyframes,
								const std::vector<mrpt::math::TPose2D>& poses)
{
	std::ostringstream j;
	j.precision(3);
	j << std::fixed << "[";
	for (size_t i = 0; i < keyframes.size(); ++i)
	{
		const mrpt::math::TPose2D& p = poses[i];
		j << (i ? ", " : "") << "{\"keyframe\": " << keyframes[i] << ", \"x\": " << p.x
		  << ", \"y\": " << p.y << ", \"phi_deg\": " << mrpt::RAD2DEG(p.phi) << "}";
	}
	return j.str() + "]";
}

// Loop closing: the searches and their outcomes, the schedule's waits and delays, the
// modelled work and the searches shed, the worker's CPU time per step.
std::string loopClosingJson(const TMapBuilderStats& s, const TLoopCloserStats& lcs)
{
	std::vector<double> closureMs;
	for (const double sec : lcs.closureSeconds) closureMs.push_back(1e3 * sec);
	const TLatencySummary closure = summarizeLatencies(closureMs);
	std::ostringstream j;
	j.precision(6);
	j << std::fixed;
	j << "  \"loop_closing\": {\"attempts\": " << lcs.attempts
	  << ", \"accepted\": " << lcs.accepted
	  << ", \"rejected_by_filters\": " << lcs.rejectedByFilters
	  << ", \"grown_retries\": " << lcs.grownRetries
	  << ", \"grown_skipped\": " << lcs.grownSkipped
	  << ", \"rejected_by_match\": " << lcs.rejectedByMatch
	  << ", \"one_pass_retries\": " << lcs.onePassRetries
	  << ", \"one_pass_matched\": " << lcs.onePassMatched
	  << ", \"rejected_by_back_end\": " << lcs.rejectedByBackEnd
	  << ", \"held_for_confirmation\": " << lcs.heldForConfirmation
	  << ", \"unconfirmed\": " << lcs.unconfirmed
	  << ", \"optimizations\": " << lcs.optimizations << ", \"rematches_refused\": "
	  << lcs.rematchesRefused
	  // The search beyond the capped window ([LoopCloser] far_search_every_keyframes).
	  << ", \"far_searches\": " << lcs.farSearches
	  << ", \"far_searches_waited\": " << lcs.farSearchesWaited
	  << ", \"far_rings\": " << lcs.farRings << ", \"far_candidates\": " << lcs.farCandidates
	  << ", \"far_confirmed\": " << lcs.farConfirmed
	  << ", \"far_rejected\": " << lcs.farRejected
	  << ", \"far_unconfirmed\": " << lcs.farUnconfirmed
	  << ", \"far_ambiguous\": " << lcs.farAmbiguous << ", \"far_closures\": "
	  << lcs.farClosures
	  // What became of far searches a later one superseded (none is dropped for its age):
	  // merged (the later window holds the places they left unchecked), or dropped, where;
	  // and those a loop closure ended.
	  << ", \"far_searches_merged\": " << lcs.farSearchesMerged
	  << ", \"far_places_merged\": " << lcs.farPlacesMerged
	  << ", \"far_searches_closed_out\": " << lcs.farSearchesClosedOut
	  << ", \"far_searches_dropped\": " << lcs.farDroppedKeyframes.size()
	  << ", \"far_searches_dropped_at\": "
	  << droppedSearchesJson(lcs.farDroppedKeyframes, lcs.farDroppedPoses)
	  // Its own lane: modelled work apart from the near searches' schedule, and CPU time
	  // (part of cpu_s's steps below, as the near searches').
	  << ", \"far_modelled_work_s\": " << 1e-3 * lcs.farWork.referenceMs()
	  << ", \"far_cpu_s\": " << lcs.farCpuSeconds
	  << ", \"gate_propagations\": " << lcs.gatePropagations
	  << ", \"gate_reuses\": " << lcs.gateReuses
	  << ", \"closure_ms\": {\"count\": " << closureMs.size()
	  << ", \"median\": " << closure.median_ms << ", \"max\": " << closure.max_ms
	  << "}"
	  // Searches run on a worker thread; the mapping thread waits for a result only when it
	  // is due (result_delay_keyframes keyframes later) and not done yet.
	  << ", \"result_waits\": " << s.loopResultWaits
	  << ", \"result_wait_s\": " << s.loopResultWaitSeconds
	  << ", \"result_wait_max_ms\": " << 1e3 * s.loopResultWaitMaxSeconds
	  << ", \"result_delay_max_keyframes\": "
	  << s.loopResultDelayMax
	  // The worker's modelled work (LoopWork.h) and the searches it deferred to keep to its
	  // budget ([LoopCloser] worker_budget_ms, worker_budget_span; "searches_shed" is
	  // "searches_deferred" under its old name), where, and what became of them: merged into
	  // a later search whose patch holds their keyframe, or dropped (no later search).
	  << ", \"modelled_work_s\": " << 1e-3 * lcs.work.referenceMs()
	  << ", \"searches_shed\": " << lcs.searchesShed
	  << ", \"searches_deferred\": " << lcs.searchesShed
	  << ", \"searches_shed_at_keyframes\": " << jsonList(lcs.shedKeyframes)
	  << ", \"searches_merged\": " << lcs.searchesMerged
	  << ", \"searches_dropped\": " << lcs.droppedKeyframes.size()
	  << ", \"searches_dropped_at\": "
	  << droppedSearchesJson(lcs.droppedKeyframes, lcs.droppedPoses)
	  // CPU time of loop closing per step (the worker thread's, whatever else runs).
	  << ", \"cpu_s\": {\"gate\": " << lcs.gateCpuSeconds
	  << ", \"correlate\": " << lcs.correlateCpuSeconds
	  << ", \"match\": " << lcs.matchCpuSeconds << ", \"close\": " << lcs.closeCpuSeconds
	  << "}},\n";
	return j.str();
}

// "stages": where the process's CPU time went (TStageTimes), each stage's share of it, and
// the wall of each stage. The mapping stage's CPU is split by thread: the mapping thread's
// reading of the input, its local registration (what the builder does with a scan besides
// placing it) and its placement (keyframes, window links and solve, loop results applied);
// the loop-closing worker thread; the rest of the other threads, the window helper of the
// local registration (patch and keyframe clouds, pairwise matches), counts with the
// placement as "keyframe_patch". "other": the mapping thread's bookkeeping between entries.
// The CPU figures add up to "process_cpu_s". Empty unless the run timed its stages.
std::string stagesJson(const TRunSummary& run, size_t scans)
{
	const TStageTimes& t = run.stages;
	if (!t.started()) return {};
	const double otherThreads = t.mapping.cpu - t.mappingThreadCpu;
	const double helper = otherThreads - t.loopWorkerCpu;
	const std::vector<std::pair<const char*, double>> cpu = {
		{"start_up", t.startUp.cpu},
		{"input", t.inputCpu},
		{"local_registration", t.feedCpu - t.placementCpu},
		{"keyframe_patch", t.placementCpu + helper},
		{"loop_closing_worker", t.loopWorkerCpu},
		{"final_optimization", t.finalOptimization.cpu},
		{"outputs", t.outputs.cpu},
		{"other", t.mappingThreadCpu - t.inputCpu - t.feedCpu}};
	double total = 0;
	for (const auto& [name, sec] : cpu) total += sec;
	std::ostringstream j;
	j.precision(6);
	j << std::fixed << "  \"stages\": {\"cpu_s\": {";
	for (size_t i = 0; i < cpu.size(); ++i)
		j << (i ? ", " : "") << "\"" << cpu[i].first << "\": " << cpu[i].second;
	j << "}, \"cpu_share\": {";
	for (size_t i = 0; i < cpu.size(); ++i)
		j << (i ? ", " : "") << "\"" << cpu[i].first
		  << "\": " << (total > 0 ? cpu[i].second / total : 0.0);
	j << "}, \"wall_s\": {\"start_up\": " << t.startUp.wall
	  << ", \"mapping\": " << t.mapping.wall
	  << ", \"final_optimization\": " << t.finalOptimization.wall
	  << ", \"outputs\": " << t.outputs.wall << "}, \"process_cpu_s\": " << total
	  << ", \"mapping_cpu_ms_per_scan\": "
	  << (scans ? 1e3 * t.mapping.cpu / double(scans) : 0.0) << "},\n";
	return j.str();
}

// The saved map this run continued (--initial-map / --localize), if any.
std::string initialMapJson(const TRunSummary& run)
{
	if (run.initialMap.empty()) return {};
	return "  \"initial_map\": {\"path\": " + jsonString(run.initialMap) +
		   ", \"keyframes\": " + std::to_string(run.initialMapKeyframes) +
		   ", \"joined\": " + (run.joined ? "true" : "false") +
		   ", \"start_found_after_scans\": " + std::to_string(run.startScans) +
		   ", \"start_attempts\": " + std::to_string(run.startAttempts) +
		   ", \"refused_by_scan_check\": " + std::to_string(run.joinsRefusedByScan) +
		   ", \"start_search_s\": " + std::to_string(run.startSeconds) +
		   ", \"replay_wait_s\": " + std::to_string(run.joinReplayWaitSeconds) +
		   ", \"frame\": " + jsonString(run.frame) + "},\n";
}

// A JSON number; null for an infinite one (an ambiguity with no second peak).
std::string jsonNumber(double v)
{
	return std::isfinite(v) ? std::to_string(v) : "null";
}

// --merge: the two maps and the transform (A <- B) the join found [m, m, deg].
std::string mergeJson(const TRunSummary& run)
{
	if (run.mergedMap.empty()) return {};
	return "  \"merge\": {\"map_a\": " + jsonString(run.initialMap) +
		   ", \"map_b\": " + jsonString(run.mergedMap) +
		   ", \"keyframes_a\": " + std::to_string(run.initialMapKeyframes) +
		   ", \"keyframes_b\": " + std::to_string(run.mergedMapKeyframes) +
		   ", \"joined\": " + (run.joined ? "true" : "false") +
		   ", \"joined_after_keyframes\": " + std::to_string(run.startScans) +
		   ", \"b_in_a\": {\"x\": " + std::to_string(run.pieceInMap.x) +
		   ", \"y\": " + std::to_string(run.pieceInMap.y) +
		   ", \"phi_deg\": " + std::to_string(mrpt::RAD2DEG(run.pieceInMap.phi)) +
		   "}, \"attempts\": " + std::to_string(run.startAttempts) +
		   ", \"score\": " + jsonNumber(run.joinScore) +
		   ", \"ambiguity\": " + jsonNumber(run.joinAmbiguity) + "},\n";
}
}  // namespace

std::string statsJson(const TRunOutputsSnapshot& snapshot)
{
	const TMapBuilderStats& s = snapshot.stats;
	const TRunSummary& run = snapshot.run;
	const TLatencySummary lat = summarizeLatencies(run.latencyMs);
	std::ostringstream j;
	j.precision(6);
	j << std::fixed;
	j << "{\n"
	  << "  \"input\": " << jsonString(run.input) << ",\n"
	  << "  \"format\": " << jsonString(run.format) << ",\n"
	  << "  \"status\": " << jsonString(run.status) << ",\n"
	  << "  \"log_entries\": " << run.logEntries << ",\n"
	  << "  \"malformed_lines\": " << run.malformedLines << ",\n"
	  << "  \"log_contents\": " << jsonCounts(run.logContents) << ",\n"
	  << "  \"scans\": " << s.scans << ",\n"
	  << "  \"keyframes\": " << s.keyframes << ",\n"
	  << "  \"keyframes_reused\": " << s.keyframesReused << ",\n"
	  << "  \"keyframes_renewed\": " << s.keyframesRenewed << ",\n"
	  << "  \"skipped_scans\": " << s.skippedScans << ",\n"
	  << "  \"unmatched_scans\": " << s.unmatchedScans << ",\n"
	  << "  \"scans_settled\": " << s.scansSettled << ",\n"
	  << "  \"keyframes_rematched\": " << s.keyframesRematched << ",\n"
	  << "  \"keyframes_left_unmatched\": " << s.keyframesLeftUnmatched << ",\n"
	  << "  \"patch_links_widened\": " << s.patchLinksWidened << ",\n"
	  << "  \"keyframes_reseeded\": " << s.keyframesReseeded << ",\n"
	  << "  \"odometry_rejected\": " << s.odometryRejected << ",\n"
	  << "  \"odometry_glitches_recovered\": " << s.glitchesRecovered << ",\n"
	  << "  \"odometry_jumps\": " << s.odometryJumps << ",\n"
	  << loopCountsJson(s)
	  // The de-skewing's laser sweep time at the end of the run [s]: [MapBuilder]
	  // scan_sweep_time_s, or estimated online from this many scan pairs (CSweepEstimator).
	  << "  \"scan_sweep_time\": {\"seconds\": " << s.sweepTime
	  << ", \"estimated\": " << (s.sweepTimeEstimated ? "true" : "false")
	  << ", \"pairs\": " << s.sweepSamples
	  << "},\n"
	  // The laser's range noise as its scans show it [m] (RangeDenoiser.h), and the scans
	  // denoised because it was over 0.1 m.
	  << "  \"range_noise\": {\"std_m\": " << s.rangeNoiseStd
	  << ", \"scans_denoised\": " << s.scansDenoised << "},\n"
	  << laserJson(snapshot.lasers) << loopClosingJson(s, snapshot.loopStats)
	  << initialMapJson(run) << mergeJson(run) << "  \"warnings\": " << run.warnings << ",\n"
	  << "  \"data_duration_s\": " << run.dataDurationSeconds << ",\n"
	  << "  \"wall_time_s\": " << run.wallSeconds << ",\n"
	  << "  \"cpu_time_s\": " << run.cpuSeconds << ",\n"
	  << "  \"real_time_factor\": "
	  << (run.wallSeconds > 0 ? run.dataDurationSeconds / run.wallSeconds : 0) << ",\n"
	  << "  \"final_optimization_s\": " << run.finalOptimizationSeconds << ",\n"
	  << "  \"peak_rss_mb\": " << run.peakRssMiB << ",\n"
	  << stagesJson(run, s.scans) << "  \"latency_ms\": {\"median\": " << lat.median_ms
	  << ", \"p99\": " << lat.p99_ms << ", \"max\": " << lat.max_ms
	  << ", \"mean\": " << lat.mean_ms << "}\n"
	  << "}\n";
	return j.str();
}

std::string statsJson(const CMetricMapBuilderLRGC& builder, const TRunSummary& run)
{
	return statsJson(snapshotRunOutputs(builder, run));
}

}  // namespace lrgc::apps
