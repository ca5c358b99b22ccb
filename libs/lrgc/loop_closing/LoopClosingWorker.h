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
 * Determinism: a job's result depends only on the job and the replica, never on when the
 * worker runs; the map builder applies it at a fixed keyframe (see TLoopCloserParams::
 * result_delay), so offline runs give the same map on any machine. With `background` off the
 * job runs inside submit() on the caller's thread: the same result, for debugging and tests.
 */
#pragma once

#include <lrgc/loop_closing/LoopCloser.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

namespace lrgc
{
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
};

/** What a job did to the replica, for the mapping thread to apply to its graph. */
struct TLoopJobResult
{
	size_t newest = 0;
	std::optional<TLoopClosure> closure;  //!< accepted loop closure, if any
	std::string rejection;  //!< why the attempt was rejected (empty if none)
	std::vector<TLink> links;  //!< links the loop closer added, in order
	std::vector<char> linkEnabled;  //!< per link: still enabled (the back-end may refuse it)
	/** New poses of nodes firstMoved..newest if the job optimised the graph, else empty. */
	size_t firstMoved = 0;
	std::vector<mrpt::math::TPose2D> poses;
};

class CLoopClosingWorker
{
   public:
	/** The loop closer's sections; a thread is started when p.background is set. */
	CLoopClosingWorker(
		const TLoopCloserParams& p, const TPatchCorrelatorParams& correlator,
		const TScanMatcherParams& matcher, const TPoseGraphOptimizerParams& optimizer);
	/** Lets the job in hand finish, then stops the thread. */
	~CLoopClosingWorker();
	CLoopClosingWorker(const CLoopClosingWorker&) = delete;
	CLoopClosingWorker& operator=(const CLoopClosingWorker&) = delete;

	/** Hands over a job; only when !pending(). Without a thread, runs it now. */
	void submit(TLoopJob job);
	/** A job was submitted and its result not yet taken. */
	bool pending() const { return m_pending; }
	/** Node of the pending job (its `newest`). */
	size_t pendingNode() const { return m_pendingNode; }
	/** The pending job is done (take() will not wait). */
	bool ready() const;
	/** The pending job's result, waiting for it if needed; rethrows what the job threw. */
	TLoopJobResult take();

	/** Counters of every job done so far. */
	TLoopCloserStats stats() const;

	/** Tests only: every job first sleeps this long (a slow machine, on purpose). */
	void setExtraDelayForTests(std::chrono::milliseconds d) { m_extraDelayMs = d.count(); }

   private:
	TLoopJobResult execute(TLoopJob& job);
	void threadMain();

	CLoopCloser m_closer;
	CPoseGraph m_replica;  //!< the mapping thread's graph as of the last job
	TScanRefs m_scans;  //!< per replica node
	std::atomic<int64_t> m_extraDelayMs{0};

	bool m_pending = false;  // touched by the mapping thread only
	size_t m_pendingNode = 0;

	mutable std::mutex m_mutex;  // guards what follows
	std::condition_variable m_cv;
	std::optional<TLoopJob> m_job;
	std::optional<TLoopJobResult> m_result;
	std::exception_ptr m_error;
	TLoopCloserStats m_stats;
	bool m_stop = false;
	std::thread m_thread;  // last: started once the rest is constructed
};

}  // namespace lrgc
