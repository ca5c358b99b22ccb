/* Consistent pose estimation (Lu & Milios; LRGC paper section 2.2) as sparse nonlinear least
 * squares on SE(2), solved by Levenberg-Marquardt with a sparse Cholesky factorisation
 * (SuiteSparse CHOLMOD; symbolic analysis reused while the sparsity pattern is unchanged).
 *
 * Residual of link i -> j with measurement Z_ij = (i <- j) and information Omega_ij:
 *     e_ij = v( Z_ij^-1 (+) (X_i^-1 (+) X_j) )      v(T) = (T.x [m], T.y [m], wrap(T.phi)
 * [rad]) chi2_ij = e_ij^T Omega_ij e_ij                 [dimensionless] The state is each
 * pose's (x, y, phi) in the map frame, updated additively (phi wrapped).
 *
 * Robustness beyond the paper (whose stated weakness is that a wrong loop closure can never
 * be undone): LoopClosure links go through Dynamic Covariance Scaling (Agarwal et al., ICRA
 * 2013), the closed form of switchable constraints. Each loop link's information is scaled by
 * s^2 with s = min(1, 2 Phi / (Phi + chi2)); this is iteratively reweighted least squares on
 * the bounded cost rho(chi2) = chi2 (chi2 <= Phi), 3 Phi - 4 Phi^2 / (Phi + chi2) (otherwise),
 * which is the objective LM minimises. A false loop closure contributes at most 3 Phi however
 * far it pulls, so it cannot bend the map. DCS is a local method, so a true loop that
 * arrives with a drift far beyond its own sigma would be switched off too; a loop link that
 * starts rejected is therefore tested against the graph's own covariance (innovation chi2 <
 * 3 Phi: closing it is cheaper than rejecting it) and, if consistent, starts with its own
 * Phi at its chi2, shrunk 4x per stage to Phi (graduated non-convexity). See
 * doc/back-end.md. Odometry and ScanMatch links are not robustified:
 * they form the spanning chain that fixes the map's shape between loops, they come from
 * overlapping consecutive scans, and a chain link given a near-zero weight would leave the
 * graph without the constraints that make the solution unique.
 */
#pragma once

#include <lrgc/common/StopToken.h>
#include <lrgc/pose_graph/PoseGraphOptimizerParams.h>
#include <mrpt/config/CLoadableOptions.h>

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <lrgc/pose_graph/PoseGraph.h>

namespace lrgc
{
namespace detail
{
class TProblem;  // the free nodes and their links (private, PoseGraphProblem.h)
}

struct TOptimizationReport
{
	int iterations = 0;                     //!< linearisations performed
	double initialChi2 = 0, finalChi2 = 0;  //!< sum of unweighted chi2 over the solved links
	double initialCost = 0, finalCost = 0;  //!< the robust objective actually minimised
	bool converged = false;  //!< a tolerance was met (false: stopped by max_iterations)
	/** A stop was requested (setStopToken) before the solve ended: the poses written back
	 * are its last accepted iterate (the input poses if it stopped before the first). */
	bool stopped = false;
	double seconds = 0;                     //!< wall time of the call [s]
	size_t numFreeNodes = 0, numLinks = 0;  //!< size of the solved problem
	/** LoopClosure link ids whose final DCS scale s < reject_scale (information scaled by
	 * s^2 < reject_scale^2): the links the back-end treats as false. Ascending. */
	std::vector<size_t> downweightedLinks;
};

class CPoseGraphOptimizer
{
public:
	explicit CPoseGraphOptimizer(const TPoseGraphOptimizerParams& params = {});
	~CPoseGraphOptimizer();
	CPoseGraphOptimizer(CPoseGraphOptimizer&&) noexcept;
	CPoseGraphOptimizer& operator=(CPoseGraphOptimizer&&) noexcept;

	const TPoseGraphOptimizerParams& params() const { return m_params; }
	/** Called at the start of every LM iteration (linearisation) of every solve: progress
	 * for a caller on another thread (CLoopClosingWorker's schedule). */
	void setIterationCallback(std::function<void()> f) { m_onIteration = std::move(f); }
	/** Solves end before their next iteration once `stop` is stopped (report.stopped). */
	void setStopToken(const CStopToken& stop) { m_stop = stop; }

	/** Optimises every node joined to `anchor` through enabled links; `anchor` stays fixed,
	 * nodes not joined to it are left untouched. Writes the poses back into `g`.
	 * `vettedLoopLinks`: ids of LoopClosure links that their caller has already found
	 * consistent with the graph's uncertainty (CLoopCloser's gate covariance); they start
	 * graduated without the back-end's own innovation test (see scheduleLoopLinks).
	 * Nodes below `frozenBelow` are held fixed too (a saved map continued as it was). */
	TOptimizationReport optimize(CPoseGraph& g, size_t anchor = 0,
								 const std::vector<size_t>& vettedLoopLinks = {},
								 size_t frozenBelow = 0) const;

	/** Optimises only `freeNodes` (e.g. the local registration window of the last K poses);
	 * every other node reached by their enabled links is held fixed. Uses per-node adjacency
	 * only: cost depends on the window and its links, not on the graph size. Throws if a
	 * group of free nodes has no link to a fixed node (its pose would be undetermined). */
	TOptimizationReport optimizeSubset(CPoseGraph& g,
									   const std::vector<size_t>& freeNodes) const;

private:
	TOptimizationReport solve(detail::TProblem& prob,
							  const std::vector<size_t>& vettedLoopLinks = {}) const;

	struct Impl;  // CHOLMOD workspace and the cached symbolic factorisation
	TPoseGraphOptimizerParams m_params;
	std::function<void()> m_onIteration;
	CStopToken m_stop;
	std::unique_ptr<Impl> m_impl;
};

/** e_ij of the header comment for poses X_i = fromInMap, X_j = toInMap and Z_ij = toInFrom.
 * If non-null, the Jacobians d e_ij / d(x_i, y_i, phi_i) and d e_ij / d(x_j, y_j, phi_j)
 * (map-frame additive perturbations) are written. */
Eigen::Vector3d linkResidual(const mrpt::math::TPose2D& fromInMap,
							 const mrpt::math::TPose2D& toInMap,
							 const mrpt::math::TPose2D& toInFrom,
							 Eigen::Matrix3d* jacFrom = nullptr,
							 Eigen::Matrix3d* jacTo = nullptr);

/** Sum of unweighted chi2 over the enabled links of `g` at its current poses. */
double totalChi2(const CPoseGraph& g);

}  // namespace lrgc
