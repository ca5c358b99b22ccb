/* What loop closing reports (stats.json "loop_closing", logs): a product of the map builder,
 * apart from CLoopCloser so that the builder's public header needs none of its internals. */
#pragma once

#include <lrgc/loop_closing/LoopWork.h>
#include <mrpt/math/TPose2D.h>

#include <cstddef>
#include <vector>

namespace lrgc
{
/** Counters for logs and stats. */
struct TLoopCloserStats
{
	size_t attempts = 0;  //!< correlations run
	size_t accepted = 0;  //!< links added
	size_t rejectedByFilters = 0, rejectedByMatch = 0, rejectedByBackEnd = 0;
	/** Near correlations tried again with the patch grown for ambiguity ([LoopCloser]
	 * patch_keyframes_per_ambiguity); each is also counted in attempts. */
	size_t grownRetries = 0;
	/** Loop links whose scan match, refused against every pass through the place, was tried
	 * again against the pass holding the nearest old keyframe alone
	 * (CLoopCloser::matchLoopLink), and those of them that matched (a retry that fails counts
	 * in rejectedByMatch too). */
	size_t onePassRetries = 0, onePassMatched = 0;
	/** Grown patches not correlated: they added fewer than [LoopCloser]
	 * patch_grown_min_new_cells of the sigma's patch's cells. */
	size_t grownSkipped = 0;
	/** Matches held until a later, independent one agrees (the gate's std above
	 * [LoopCloser] confirm_above_sigma_m), and those dropped because the next disagreed or
	 * none came. */
	size_t heldForConfirmation = 0, unconfirmed = 0;
	/** The search beyond the capped window ([LoopCloser] far_search_every_keyframes): far
	 * searches run, and the capped checks that found the far lane busy; the distinct
	 * places they proposed (candidates), those the full-resolution search and the scan match
	 * confirmed and those they rejected; held places dropped because a later patch confirmed
	 * none of them or more than one (ambiguous); loops closed so. */
	size_t farSearches = 0, farSearchesWaited = 0;
	/** Rings of far_window_xy_m the far searches' windows held, summed (farSearches of them
	 * the first rings: the rest reached beyond far_window_xy_m). */
	size_t farRings = 0;
	size_t farCandidates = 0, farConfirmed = 0, farRejected = 0;
	size_t farUnconfirmed = 0, farAmbiguous = 0, farClosures = 0;
	/** Far searches a later one superseded before they had checked all their places
	 * (far_search_every_keyframes capped checks after they started, their rings done):
	 * merged when the later search's window holds every place left unchecked (it searches
	 * them again with a newer patch), else dropped; the places so left unchecked; and far
	 * searches ended by a loop closure (the old map moved under them). None is dropped for its
	 * age: a search whose rings take long goes on to its end. */
	size_t farSearchesMerged = 0, farPlacesMerged = 0, farSearchesClosedOut = 0;
	/** The far searches dropped: their keyframes and those keyframes' poses [map frame]. */
	std::vector<size_t> farDroppedKeyframes;
	std::vector<mrpt::math::TPose2D> farDroppedPoses;
	size_t optimizations = 0;
	/** Re-matches after a closure that disagreed with the solved poses (not linked). */
	size_t rematchesRefused = 0;
	/** Gates by a propagation over the whole graph, and by reuse of the last one
	 * ([LoopCloser] gate_reuse_keyframes). */
	size_t gatePropagations = 0, gateReuses = 0;
	std::vector<double> closureSeconds;  //!< per optimised closure
	/** CPU time of the thread that ran loop closing, per step of CLoopCloser [s]: the gate
	 * (uncertainty propagation), the correlation (old-map grid and search), the link's scan
	 * match (reference cloud and match) and the closure (solves and re-matching). */
	double gateCpuSeconds = 0, correlateCpuSeconds = 0, matchCpuSeconds = 0,
		   closeCpuSeconds = 0;
	/** CPU time of the worker thread over its whole jobs [s]: the steps above and the
	 * replica's bookkeeping; 0 when the jobs run on the mapping thread (`background` off). */
	double workerThreadCpuSeconds = 0;
	/** The same work in machine-independent counts (the worker's schedule, LoopWork.h). */
	TLoopWork work;
	/** The far search's own lane (CLoopCloser::setSchedule): its work in the same counts,
	 * apart from `work`, and its CPU time [s] (also in the steps' CPU times above, apart
	 * from a loop it closes, counted in `work` and closeCpuSeconds). */
	TLoopWork farWork;
	double farCpuSeconds = 0;
	double farThreadCpuSeconds = 0;  //!< the part of it on the far lane's own thread [s]
	/** Searches the worker deferred because its modelled schedule ran more than
	 * [LoopCloser] max_backlog_keyframes keyframes' budget behind (CLoopClosingWorker). */
	size_t searchesShed = 0;
	/** Where: the keyframe (graph node) of each search deferred, in order. */
	std::vector<size_t> shedKeyframes;
	/** Deferred searches merged into a later search whose patch holds their keyframe (their
	 * place was searched). */
	size_t searchesMerged = 0;
	/** Deferred searches no later search covered (issue 28: none may be): their keyframes
	 * and those keyframes' poses [map frame] when dropped. CLoopClosingWorker::stats() counts
	 * the searches deferred since the last one that ran as dropped until a later search
	 * merges them (at the end of a run: none will). */
	std::vector<size_t> droppedKeyframes;
	std::vector<mrpt::math::TPose2D> droppedPoses;
};

}  // namespace lrgc
