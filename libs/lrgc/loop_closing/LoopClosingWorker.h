/* CLoopClosingWorker: loop closing in the background (Gutmann & Konolige 2000, section 1:
 * correlation "operates in a 'background' mode, checking for matches against the old map
 * whenever the robot moves to an appropriate location"; section 2.3: "we intend to run it
 * constantly in the background").
 *
 * The worker owns a CLoopCloser and its own copy of the pose graph (the replica). At a
 * keyframe k the mapping thread hands it a job: what changed in its graph since the last job
 * (new nodes and their scans, poses it moved, links it added). The worker brings the replica
 * up to date, looks for a loop for node k and closes it there (correlation, scan match,
 * whole-graph optimisation, re-matching), and hands back the links it added and, if it moved
 * the map, the new poses of nodes 0..k. Meanwhile the mapping thread keeps registering scans.
 *
 * Keeping the replica in step costs only what changed (the local window's poses, the new
 * nodes and links), not a copy of the whole graph per job.
 *
 * Jobs queue up: a search starts at every keyframe, and its result is applied by the mapping
 * thread some keyframes later, in order. A job handed over before an earlier job's result was
 * applied carries poses in the frame the mapping thread had then, without that correction:
 * the worker corrects them itself as the mapping thread will (a node the result placed keeps
 * the result's pose; a node added after it is carried along by the correction of the result's
 * newest node, X_i <- X'_k (+) (M_k^-1 (+) M_i), M being the mapping thread's poses).
 *
 * Determinism: a job's result depends only on the jobs so far, never on when the worker runs;
 * the map builder applies it at a keyframe fixed by the log alone, so offline runs give the
 * same map on any machine: k + result_delay_keyframes, or, with [LoopCloser] worker_budget_ms,
 * the keyframe where a modelled worker would finish it. The modelled worker's time is the
 * work it may have done, its grant G [ms]: every keyframe taken (new or reused: on known
 * ground the robot reuses keyframes and adds no node, and results must still land) grants it
 *     g = worker_budget_ms * clamp(s / worker_budget_span, 1, kMaxGrantKeyframes)    [ms]
 * with s the robot's travel since the previous keyframe in keyframe spacings (the map
 * builder's; path / keyframe_distance_m or turn / keyframe_angle, the larger): the budget
 * follows the data, so a sparse log, where one scan step spans several spacings, gets the
 * work of the keyframes it stands for; a dense log, whose keyframes are taken just past one
 * spacing, keeps worker_budget_ms per keyframe, and a stop grants nothing. One job after the
 * other:
 *     start_j = max(G_j, finish_{j-1}),  finish_j = start_j + W_j               [ms of grant]
 * with G_j the grant when job j was handed over and W_j its modelled work [ms]; the result is
 * due at the first keyframe clock c >= k_j + result_delay_keyframes whose grant G(c) >=
 * finish_j. A job that would start more than max_backlog_keyframes * worker_budget_ms behind
 * its grant defers its search, unless the last search ran patch_min_keyframes keyframes before
 * it or more: while behind, searches are thinned out, never stopped. A deferred search is
 * merged into the next search that runs when its keyframe lies in that search's patch (a
 * patch is at least patch_min_keyframes long: its place is searched), else dropped, and
 * stats() says which and where (issue 28); at the run's end a last job searches the newest
 * keyframe if searches are still deferred. While a job runs, the worker publishes the least
 * finish its work so far implies, so the mapping thread waits only when the real worker is
 * slower than the modelled one. With `background` off a job runs inside submit() on the
 * caller's thread: the same results, for debugging and tests.
 */
#pragma once

#include <lrgc/loop_closing/LoopCloser.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

namespace lrgc
{
struct TLoopClosingTestAccess;

/** What the mapping thread's graph gained or changed since the previous job. */
struct TLoopJob
{
	size_t newest = 0;  //!< look for a loop for this node (the newest keyframe)
	/** Poses of nodes firstPose, firstPose + 1, ..., newest [map frame]: every node added or
	 * moved since the previous job (moved: takeLowestMovedNode()). */
	size_t firstPose = 0;
	std::vector<mrpt::math::TPose2D> poses;
	std::vector<TLink> links;  //!< links added by the mapping thread since the previous job
	TScanRefs scans;  //!< scans of the nodes added since the previous job, in node order
	size_t resultsApplied = 0;  //!< results the mapping thread had applied when handing it over
	/** The mapping thread's keyframe clock when handing it over: keyframes taken so far, new
	 * or reused (result_delay_keyframes counts in it). */
	size_t clock = 0;
	double grantMs = 0;  //!< the modelled worker's grant G at hand-over [ms] (see the header)
	/** The loop closer's stop token for this job (CLoopCloser::setStopToken): a job stopped
	 * part-way adds nothing. */
	CStopToken stop;
	size_t frozenNodes = 0;  //!< nodes below it are held fixed (CLoopCloser::setFrozenNodes)
	/** The run's end (CLoopClosing::searchDeferred): no new node; searches `newest` only if
	 * searches were deferred since the last one, whatever the backlog. */
	bool runsEnd = false;
};

/** What a job did to the replica, for the mapping thread to apply to its graph. */
struct TLoopJobResult
{
	size_t newest = 0;
	std::optional<TLoopClosure> closure;  //!< accepted loop closure, if any
	std::vector<TLink> links;             //!< links the loop closer added, in order
	std::vector<char> linkEnabled;  //!< per link: still enabled (the back-end may refuse it)
	/** New poses of nodes firstMoved..newest if the job optimised the graph, else empty. */
	size_t firstMoved = 0;
	std::vector<mrpt::math::TPose2D> poses;
	size_t clock = 0;  //!< the job's clock
	/** The modelled worker's finish [ms of grant]: due once the grant reaches it. */
	double finishMs = 0;
};

class CLoopClosingWorker
{
public:
	/** The loop closer's sections; a thread is started when p.background is set. */
	CLoopClosingWorker(const TLoopCloserParams& p, const TPatchCorrelatorParams& correlator,
					   const TScanMatcherParams& matcher,
					   const TPoseGraphOptimizerParams& optimizer);
	/** Lets the job in hand finish, drops the queued ones, and stops the thread. */
	~CLoopClosingWorker();
	CLoopClosingWorker(const CLoopClosingWorker&) = delete;
	CLoopClosingWorker& operator=(const CLoopClosingWorker&) = delete;

	/** Queues a job. Without a thread, runs it now. */
	void submit(TLoopJob job);
	/** Jobs submitted whose results were not yet taken. */
	size_t pending() const { return m_pendingClocks.size(); }
	/** The oldest pending job is done (take() will not wait). */
	bool ready() const;
	/** Whether the oldest pending job's result is due at keyframe clock `clock`, with the
	 * modelled worker's grant `grantMs` [ms] then. Waits only while that cannot be told yet
	 * (the job is still running and its work so far does not put it past `grantMs`); the time
	 * waited is added to `waitedSeconds`. */
	bool due(size_t clock, double grantMs, double& waitedSeconds);
	/** What a keyframe taken `span` keyframe spacings of travel after the previous one adds
	 * to the modelled worker's grant [ms] (see the header). */
	double keyframeGrantMs(double span) const;
	/** The oldest pending job's result, waiting for it if needed; rethrows what the job
	 * threw. */
	TLoopJobResult take();

	/** Counters of every job done so far. */
	TLoopCloserStats stats() const;

private:
	friend struct TLoopClosingTestAccess;  // tests: a slow machine (m_extraDelayMs)

	/** A result that moved poses, until the mapping thread has applied it. */
	struct TCorrection
	{
		size_t sequence = 0;  //!< of its job (0, 1, 2, ...)
		size_t newest = 0, firstMoved = 0;
		mrpt::math::TPose2D newestPose;  //!< X'_k, the result's pose of its newest node
	};

	TLoopJobResult execute(TLoopJob& job);
	/** Whether a result of a job handed over at `jobClock` that finishes at `finishMs` is due
	 * at keyframe clock `clock` with grant `grantMs`. */
	bool isDue(size_t jobClock, double finishMs, size_t clock, double grantMs) const;
	/** Searches `job.newest` unless the backlog defers it (see the header); merges or drops
	 * the searches deferred before it. */
	std::optional<TLoopClosure> searchOrDefer(const TLoopJob& job, double start);
	void publishProgress(double finishMs);
	/** The far lane's step due after the job just done (CLoopCloser::farStep), run once its
	 * result is handed over; it moves nothing in the replica. */
	void farStep();
	/** m_stats from the loop closer's (m_mutex held). */
	void publishStats();
	void updateReplica(const TLoopJob& job);
	void threadMain();

	const size_t m_resultDelay;
	const double m_budgetMs;    //!< worker_budget_ms (0: results at k + result_delay_keyframes)
	const double m_budgetSpan;  //!< worker_budget_span [keyframe spacings]
	const double m_maxBacklogMs;     //!< max_backlog_keyframes * worker_budget_ms [ms]
	const size_t m_searchSpacing;    //!< patch_min_keyframes: the thinned searches' spacing
	size_t m_lastSearched = 0;       //!< newest node of the last job that searched
	std::vector<size_t> m_deferred;  //!< nodes whose search was deferred, none run since
	CLoopCloser m_closer;
	CPoseGraph m_replica;  //!< the mapping thread's graph as of the last job, corrected
	TScanRefs m_scans;     //!< per replica node
	/** The poses as the mapping thread sent them (M), for the corrections it has not applied.
	 */
	std::vector<mrpt::math::TPose2D> m_sentPoses;
	std::vector<TCorrection> m_unapplied;
	size_t m_jobsDone = 0;
	double m_modelledFree = 0;  //!< grant at which the modelled worker is free [ms]
	std::atomic<int64_t> m_extraDelayMs{0};  //!< tests: every job first sleeps this long [ms]

	std::deque<size_t> m_pendingClocks;  // of the jobs not taken; the mapping thread's
	size_t m_taken = 0;                  // results taken (the mapping thread's)

	mutable std::mutex m_mutex;  // guards what follows
	std::condition_variable m_cv;
	std::deque<TLoopJob> m_jobs;
	std::deque<TLoopJobResult> m_results;
	/** The job running (its sequence number, SIZE_MAX: none) and the least due keyframe
	 * its work so far implies [ms of grant]. */
	size_t m_runningJob = SIZE_MAX;
	double m_runningFinishMs = 0;
	std::exception_ptr m_error;
	TLoopCloserStats m_stats;
	double m_threadCpuSeconds = 0;  //!< the worker thread's, over its jobs [s]
	bool m_stop = false;
	std::thread m_thread;  // last: started once the rest is constructed
};

}  // namespace lrgc
