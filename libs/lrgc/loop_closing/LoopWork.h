/* TLoopWork: what the loop closer did, counted in units that do not depend on the machine,
 * and the model that turns those counts into the time a reference machine takes.
 *
 * Offline runs must give the same map on any machine (issue 12), so the keyframe at which a
 * loop search's result is applied cannot depend on how long the worker really took. It
 * depends on how long the work *should* take: CLoopClosingWorker runs a virtual worker that
 * does [LoopCloser] worker_budget_ms of modelled work per keyframe (more for a keyframe that
 * spans several keyframe spacings of travel: worker_budget_span), and applies each result
 * at the keyframe the virtual worker finishes it. A cheap search is applied at the next
 * keyframe, a whole-graph closure of Killian (~1 s) a few hundred keyframes later, and the
 * mapping thread waits only when the real worker is slower than the model says.
 *
 * The model is linear in the counts, per step of CLoopCloser::process:
 *   gate       a_g + b_n nodes propagated + b_l labels reused
 *   correlate  a_c + b_a (headings x patch cells) + b_p (poses scored x patch cells)
 *   match      a_m + b_r reference points
 *   close      sum over solves: b_s (nodes + links) + b_i iterations (nodes + links)
 *   job        a_j + b_j new scans (the replica's update)
 *   far map    b_f old-map points of a far search (CLoopCloser::startFarSearch: every old
 *              point moved into the map frame and rasterised into the coarse grid)
 * Coefficients: non-negative least squares on the per-job thread CPU time of Intel and MIT
 * Killian (6973 jobs) on the development machine (2 cores, Release): per job the model's
 * total is within 0.5x-1.9x of the measured time for jobs over 20 ms, and the two logs'
 * totals within 0.3 %. b_f is not in that fit (no far search ran there): measured on the
 * hall loop of tests/large_loop_test.cpp, 10 far maps of 79k-189k points took 2.1-4.5 ms of
 * thread CPU, a_c (counted as the search's correlation) plus 0.8-1.7e-5 ms per point.
 */
#pragma once

#include <cstddef>

namespace lrgc
{
struct TLoopWork
{
	size_t jobs = 0, newScans = 0;
	size_t gatePropagatedNodes = 0;  //!< nodes of the graph at each whole-graph propagation
	size_t gateReusedLabels = 0;     //!< labels chained by gate reuse
	size_t correlations = 0;
	double correlationAngleCells = 0;   //!< sum of headings x distinct patch cells
	double correlationPoseCells = 0;    //!< sum of poses scored x distinct patch cells
	size_t matches = 0;                 //!< loop link scan matches (step 3)
	size_t matchRefPoints = 0;          //!< points of the old scans they were built from
	size_t farMapPoints = 0;            //!< old-map points of the far searches' grids
	double solveElements = 0;           //!< sum over whole-graph solves of nodes + links
	double solveIterationElements = 0;  //!< the same, times the solve's iterations

	/** Modelled time of this work on the reference machine [ms]. */
	double referenceMs() const;

	TLoopWork& operator+=(const TLoopWork& o);
	TLoopWork operator-(const TLoopWork& o) const;
};

}  // namespace lrgc
