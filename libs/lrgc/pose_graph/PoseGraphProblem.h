/* Private to CPoseGraphOptimizer: one least-squares problem cut out of a CPoseGraph (the
 * free nodes and the enabled links touching them) and its block-sparse normal equations.
 * Kept apart from PoseGraphOptimizer.cpp so that the LM loop and the CHOLMOD calls read on
 * their own. Not installed, not part of the API. */
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <vector>

#include <lrgc/pose_graph/PoseGraph.h>

namespace lrgc::detail
{
/** Dynamic Covariance Scaling on LoopClosure links (PoseGraphOptimizer.h), with the
 * graduated schedule: a link with a start value phiStart uses max(phi, phiStart / divisor). */
struct TCostKernel
{
	bool robust = true;
	double phi = 5.0;      // target Phi [chi2]
	double divisor = 1.0;  // grows 4x per graduated stage
	double phiFor(double phiStart) const { return std::max(phi, phiStart / divisor); }
	/** DCS scale s = min(1, 2 phi / (phi + chi2)); the link's weight is s^2. */
	static double scale(double chi2, double phi)
	{
		return chi2 <= phi ? 1.0 : 2 * phi / (phi + chi2);
	}
	/** rho(chi2): chi2 up to phi, then 3 phi - 4 phi^2 / (phi + chi2) (d rho/d chi2 = s^2). */
	static double cost(double chi2, double phi)
	{
		return chi2 <= phi ? chi2 : 3 * phi - 4 * phi * phi / (phi + chi2);
	}
};

/** Upper triangle of H (CSC, scalar index 3 k + {x, y, phi} for variable k) and gradient. */
struct TNormalEquations
{
	std::vector<int> colPtr, rowIdx;
	std::vector<double> values;
	std::vector<int> diagPos;                   // position of H(k, k) in values
	Eigen::VectorXd rhs;                        // g = sum J^T (s^2 Omega) e
	std::vector<int> blockColPtr, blockRowIdx;  // the same pattern, one entry per 3x3 block
};

struct TProblemLink
{
	size_t id = 0;                           // link id in the graph
	int vi = -1, vj = -1;                    // variable index of from / to, -1 if held fixed
	mrpt::math::TPose2D fixedFrom, fixedTo;  // poses of fixed endpoints
	mrpt::math::TPose2D z;
	Eigen::Matrix3d info;
	bool loopClosure = false;
	int offBlock = -1;    // both free: index of the (min, max) block within its block column
	double phiStart = 0;  // graduated schedule start (0: the target Phi from the start)
};

class TProblem
{
public:
	/** Every node joined to `anchor` by enabled links is free except `anchor`. O(n + m). */
	static TProblem wholeGraph(const CPoseGraph& g, size_t anchor, size_t frozenBelow = 0);
	/** `freeNodes` free, everything else fixed; touches only their adjacency lists. */
	static TProblem subset(const CPoseGraph& g, const std::vector<size_t>& freeNodes);

	/** Returns the unweighted chi2 at poses `x` of the variables; *cost = robust cost. */
	double evaluate(const std::vector<mrpt::math::TPose2D>& x, const TCostKernel& k,
					double* cost) const;
	/** Fills `ne` at the current x (pattern computed on the first call). */
	void linearize(const TCostKernel& k, TNormalEquations& ne);
	/** Residual and unweighted chi2 of link l at the current x. */
	Eigen::Vector3d residual(const TProblemLink& l, Eigen::Matrix3d* Ji = nullptr,
							 Eigen::Matrix3d* Jj = nullptr) const;
	/** Ids of LoopClosure links with DCS scale (target Phi) < reject_scale at the current x. */
	std::vector<size_t> rejectedLoopLinks(const TCostKernel& k, double reject_scale) const;
	void writeBack(CPoseGraph& g) const;

	std::vector<size_t> varNode;         // variable k -> node index
	std::vector<mrpt::math::TPose2D> x;  // current poses of the variables (map <- robot)
	std::vector<TProblemLink> links;

private:
	void addLink(const CPoseGraph& g, size_t id, int vi, int vj);
	void buildPattern(TNormalEquations& ne);
	bool m_patternBuilt = false;
};

}  // namespace lrgc::detail
