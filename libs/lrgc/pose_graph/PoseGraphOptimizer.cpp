/* Levenberg-Marquardt on the SE(2) pose graph with CHOLMOD (see PoseGraphOptimizer.h for
 * the formulation and the robust kernel).
 *
 * Each solve builds a TProblem: the free nodes (variables, 3 scalars each) and the enabled
 * links touching them, with fixed endpoints copied in. The normal equations are assembled
 * into a block-sparse upper-triangular CSC matrix whose pattern is built once per solve; the
 * LM loop then only rewrites values. CHOLMOD's symbolic analysis (fill-reducing ordering
 * of the block graph, elimination tree, column counts) is kept in the optimizer and reused
 * while the pattern is unchanged, across iterations and across calls. Loop links that start
 * rejected but are consistent with the graph's covariance start graduated (see
 * scheduleLoopLinks below).
 *
 * LM (Nielsen's damping update): (H + lambda diag(H)) dx = -g, gain ratio = actual cost
 * decrease / decrease predicted by the weighted quadratic model.
 */
#include <lrgc/pose_graph/PoseGraphOptimizer.h>

#include <cholmod.h>
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/exceptions.h>
#include <Eigen/Cholesky>
#include <Eigen/LU>

#include <dlfcn.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>

#include "PoseGraphProblem.h"
#include <lrgc/common/params_io.h>
#include <lrgc/common/se2.h>

namespace lrgc
{
// ------------------------------------------------------------------------------ residual
/* e = ( R_z^T (R_i^T (t_j - t_i) - t_z) ,  wrap(phi_j - phi_i - phi_z) )
 * with t = (x, y) [m] in the map frame (t_z in frame i), R_a the rotation by phi_a [rad].
 * Let tD = R_i^T (t_j - t_i) (node j's position in frame i) and A = R_z^T R_i^T:
 *   d e_xy  / d t_j   =  A                d e_xy  / d t_i   = -A          [m/m]
 *   d e_xy  / d phi_i =  R_z^T (tD.y, -tD.x)^T                             [m/rad]
 *   d e_xy  / d phi_j =  0
 *   d e_phi / d phi_j =  1                d e_phi / d phi_i = -1           [rad/rad]
 *   d e_phi / d t     =  0 */
Eigen::Vector3d linkResidual(const TPose2D& xi, const TPose2D& xj, const TPose2D& z,
							 Eigen::Matrix3d* Ji, Eigen::Matrix3d* Jj)
{
	const TPose2D d = between(xi, xj);
	const TPose2D e = between(z, d);
	if (Ji || Jj)
	{
		const double a = -(xi.phi + z.phi), ca = std::cos(a), sa = std::sin(a);
		Eigen::Matrix2d A;
		A << ca, -sa, sa, ca;
		const double cz = std::cos(z.phi), sz = std::sin(z.phi);
		const Eigen::Vector2d dPhi(cz * d.y + sz * (-d.x), -sz * d.y + cz * (-d.x));
		if (Ji)
		{
			Ji->setZero();
			Ji->topLeftCorner<2, 2>() = -A;
			Ji->block<2, 1>(0, 2) = dPhi;
			(*Ji)(2, 2) = -1;
		}
		if (Jj)
		{
			Jj->setZero();
			Jj->topLeftCorner<2, 2>() = A;
			(*Jj)(2, 2) = 1;
		}
	}
	return {e.x, e.y, e.phi};
}

double totalChi2(const CPoseGraph& g)
{
	double sum = 0;
	for (size_t id = 0; id < g.numLinks(); ++id)
	{
		if (!g.isLinkEnabled(id)) continue;
		const TLink& l = g.link(id);
		const Eigen::Vector3d e = linkResidual(g.pose(l.from), g.pose(l.to), l.toInFrom);
		sum += e.dot(l.information * e);
	}
	return sum;
}

// --------------------------------------------------------------- sparse Cholesky (CHOLMOD)
namespace
{
/** Debian's CHOLMOD is built with OpenMP, and a run's poses then depended on the threads
 * OpenMP chose for it: two runs of Intel at once differed in the last digits of
 * trajectory.tum (1 pair in 3), never with OMP_NUM_THREADS=1 (3 of 3 the same). One thread
 * for this calling thread's parallel regions (an ICV per thread: the mapping thread and the
 * loop-closing worker each call this), looked up at run time because lrgc itself is not
 * built with OpenMP; a CHOLMOD without OpenMP has no such symbol and needs nothing. */
void useOneOpenMpThread()
{
	using TSetNumThreads = void (*)(int);
	static const auto set =
		reinterpret_cast<TSetNumThreads>(dlsym(RTLD_DEFAULT, "omp_set_num_threads"));
	if (set) set(1);
}

/** (H + lambda diag(H)) dx = -g by CHOLMOD's simplicial LL^T (the supernodal variant is
 * slower with the reference BLAS of Debian). The fill-reducing ordering is computed on the
 * 3x3-block pattern (one vertex per pose: METIS nested dissection, AMD if METIS fails),
 * expanded to scalars, and kept with the symbolic factor while the pattern is unchanged. */
class CCholmodSolver
{
public:
	CCholmodSolver()
	{
		cholmod_start(&m_c);
		m_c.print = 0;  // library code never prints
		m_c.supernodal = CHOLMOD_SIMPLICIAL;
		m_c.final_ll = 1;
	}
	~CCholmodSolver()
	{
		if (m_L) cholmod_free_factor(&m_L, &m_c);
		if (m_A) cholmod_free_sparse(&m_A, &m_c);
		cholmod_finish(&m_c);
	}
	CCholmodSolver(const CCholmodSolver&) = delete;
	CCholmodSolver& operator=(const CCholmodSolver&) = delete;

	/** Factorises H + lambda diag(H); false if not positive definite. */
	bool factorize(const detail::TNormalEquations& ne, double lambda)
	{
		useOneOpenMpThread();
		if (!m_L || ne.colPtr != m_colPtr || ne.rowIdx != m_rowIdx) analyze(ne);
		double* Ax = static_cast<double*>(m_A->x);
		std::copy(ne.values.begin(), ne.values.end(), Ax);
		for (int d : ne.diagPos) Ax[d] += lambda * ne.values[d];
		cholmod_factorize(m_A, m_L, &m_c);
		return m_c.status != CHOLMOD_NOT_POSDEF && m_L->minor >= m_A->nrow;
	}

	/** dx = -(factorised matrix)^-1 g. */
	bool solve(const Eigen::VectorXd& g, Eigen::VectorXd& dx)
	{
		const size_t n = m_A->nrow;
		cholmod_dense* b = cholmod_allocate_dense(n, 1, n, CHOLMOD_REAL, &m_c);
		ASSERT_(b != nullptr);
		Eigen::Map<Eigen::VectorXd>(static_cast<double*>(b->x), n) = -g;
		cholmod_dense* x = cholmod_solve(CHOLMOD_A, m_L, b, &m_c);
		cholmod_free_dense(&b, &m_c);
		ASSERT_(x != nullptr);
		dx = Eigen::Map<const Eigen::VectorXd>(static_cast<double*>(x->x), n);
		cholmod_free_dense(&x, &m_c);
		return dx.allFinite();
	}

	/** J M^-1 J^T for the factorised matrix M and a 3 x n matrix J whose nonzero columns
	 * are `idx` (holding Jc): three solves. */
	Eigen::Matrix3d projectedInverse(const std::vector<int>& idx, const Eigen::MatrixXd& Jc)
	{
		const size_t n = m_A->nrow;
		cholmod_dense* b = cholmod_zeros(n, 3, CHOLMOD_REAL, &m_c);
		ASSERT_(b != nullptr);
		double* bx = static_cast<double*>(b->x);
		for (size_t k = 0; k < idx.size(); ++k)
			for (int r = 0; r < 3; ++r) bx[r * n + idx[k]] = Jc(r, k);
		cholmod_dense* x = cholmod_solve(CHOLMOD_A, m_L, b, &m_c);
		cholmod_free_dense(&b, &m_c);
		ASSERT_(x != nullptr);
		const double* xx = static_cast<const double*>(x->x);
		Eigen::Matrix3d out = Eigen::Matrix3d::Zero();
		for (int c = 0; c < 3; ++c)
			for (size_t k = 0; k < idx.size(); ++k)
				for (int r = 0; r < 3; ++r) out(r, c) += Jc(r, k) * xx[c * n + idx[k]];
		cholmod_free_dense(&x, &m_c);
		return 0.5 * (out + out.transpose());
	}

private:
	void analyze(const detail::TNormalEquations& ne)
	{
		if (m_L) cholmod_free_factor(&m_L, &m_c);
		if (m_A) cholmod_free_sparse(&m_A, &m_c);
		const size_t n = ne.rhs.size(), m = n / 3;
		m_A = cholmod_allocate_sparse(n, n, ne.values.size(), 1, 1, 1, CHOLMOD_REAL, &m_c);
		ASSERT_(m_A != nullptr);
		std::copy(ne.colPtr.begin(), ne.colPtr.end(), static_cast<int*>(m_A->p));
		std::copy(ne.rowIdx.begin(), ne.rowIdx.end(), static_cast<int*>(m_A->i));
		m_colPtr = ne.colPtr;
		m_rowIdx = ne.rowIdx;

		// Ordering of the block graph, expanded to the scalar unknowns.
		cholmod_sparse* B = cholmod_allocate_sparse(m, m, ne.blockRowIdx.size(), 1, 1, 1,
													CHOLMOD_PATTERN, &m_c);
		ASSERT_(B != nullptr);
		std::copy(ne.blockColPtr.begin(), ne.blockColPtr.end(), static_cast<int*>(B->p));
		std::copy(ne.blockRowIdx.begin(), ne.blockRowIdx.end(), static_cast<int*>(B->i));
		std::vector<int> blockPerm(m), perm(n);
		{
			// Debian's METIS seeds libc's rand() at each call and draws from it (one state
			// per process): two threads ordering at once (the mapping thread's window solve,
			// the loop-closing worker's) interleave their draws, and the ordering, hence the
			// last digits of the poses, changed from run to run (Intel: 6 different
			// trajectory.tum in 9 runs; 3 of 3 the same without the worker thread, 4 of 4
			// with this lock). One ordering at a time.
			static std::mutex metisMutex;
			const std::lock_guard<std::mutex> lock(metisMutex);
			if (!cholmod_metis(B, nullptr, 0, 1, blockPerm.data(), &m_c))
				cholmod_amd(B, nullptr, 0, blockPerm.data(), &m_c);
		}
		cholmod_free_sparse(&B, &m_c);
		for (size_t k = 0; k < m; ++k)
			for (int r = 0; r < 3; ++r) perm[3 * k + r] = 3 * blockPerm[k] + r;
		m_c.nmethods = 1;
		m_c.method[0].ordering = CHOLMOD_GIVEN;
		m_L = cholmod_analyze_p(m_A, perm.data(), nullptr, 0, &m_c);
		ASSERT_(m_L != nullptr);
	}

	cholmod_common m_c{};
	cholmod_sparse* m_A = nullptr;  // pattern of H (upper), values rewritten per factorisation
	cholmod_factor* m_L = nullptr;  // symbolic analysis for m_A's pattern
	std::vector<int> m_colPtr, m_rowIdx;
};

// --------------------------------------------------------------------- Levenberg-Marquardt
struct TPass
{
	int iterations = 0;
	bool converged = false;
	bool stopped = false;  //!< a stop was requested: prob.x is the last accepted iterate
};

/** Where LM reports its iterations and learns of a stop request. */
struct TLoopHooks
{
	const std::function<void()>& onIteration;
	const CStopToken& stop;
};

/** LM on the problem's robust cost with kernel `k`, from prob.x, updating it. Stops when
 * the relative cost decrease < relTol, the step < stepTol, after max_iterations, or before
 * an iteration once a stop is requested. */
TPass levenbergMarquardt(detail::TProblem& prob, const detail::TCostKernel& k,
						 const TPoseGraphOptimizerParams& p, double relTol, int max_iterations,
						 CCholmodSolver& solver, detail::TNormalEquations& ne,
						 const TLoopHooks& hooks)
{
	TPass pass;
	pass.converged = prob.varNode.empty();
	double cost = 0, lambda = p.initial_lambda, nu = 2;
	prob.evaluate(prob.x, k, &cost);
	Eigen::VectorXd dx;
	std::vector<TPose2D> trial;
	while (!pass.converged && pass.iterations < max_iterations)
	{
		if (hooks.stop.stopRequested()) return pass.stopped = true, pass;
		++pass.iterations;
		if (hooks.onIteration) hooks.onIteration();
		prob.linearize(k, ne);
		if (ne.rhs.cwiseAbs().maxCoeff() < 1e-12) return pass.converged = true, pass;
		bool accepted = false;
		while (!accepted && lambda < 1e16)
		{
			if (!solver.factorize(ne, lambda) || !solver.solve(ne.rhs, dx))
			{
				lambda *= nu, nu *= 2;
				continue;
			}
			trial = prob.x;
			for (size_t v = 0; v < trial.size(); ++v)
				trial[v] = {trial[v].x + dx[3 * v], trial[v].y + dx[3 * v + 1],
							mrpt::math::wrapToPi(trial[v].phi + dx[3 * v + 2])};
			double newCost = 0;
			prob.evaluate(trial, k, &newCost);
			// Decrease predicted by the quadratic model: -g.dx + lambda dx^T diag(H) dx.
			double dDx = 0;
			for (int i = 0; i < dx.size(); ++i) dDx += dx[i] * dx[i] * ne.values[ne.diagPos[i]];
			const double predicted = -ne.rhs.dot(dx) + lambda * dDx;
			const double rho = (cost - newCost) / std::max(predicted, 1e-300);
			const bool tinyStep = dx.cwiseAbs().maxCoeff() < p.step_tolerance;
			if (newCost < cost && rho > 0)
			{
				accepted = true;
				const double relDecrease = (cost - newCost) / std::max(cost, 1e-300);
				prob.x.swap(trial);
				cost = newCost;
				lambda *= std::max(1.0 / 3.0, 1.0 - std::pow(2 * rho - 1, 3));
				nu = 2;
				pass.converged = relDecrease < relTol || tinyStep;
			}
			else if (tinyStep)
				break;
			else
				lambda *= nu, nu *= 2;
		}
		if (!accepted) pass.converged = true;  // no descent step left: numerical minimum
	}
	return pass;
}

/* Which loop links start graduated. DCS alone is a local method: a loop link that starts
 * far outside its quadratic zone (a true loop arriving with the drift of a long cycle) gets
 * a tiny weight and pulls the map to itself only over very many iterations, so it would end
 * rejected although the graph can absorb it. Each loop link that would be reported rejected
 * at the start (DCS scale s < reject_scale) is therefore tested against the graph's own
 * uncertainty: with H the DCS-weighted normal matrix and J = [J_from J_to] (free endpoints),
 *     innovation chi2 = e^T (J H^-1 J^T + Omega^-1)^-1 e  [-],
 * the chi2 the rest of the graph would take on if it closed the link (linearised). If it is
 * below 3 Phi, the bound of DCS's penalty for rejecting the link, the objective prefers the
 * link closed, and the link starts graduated: its own Phi begins at its chi2 (least squares
 * for it) and is divided by 4 per stage down to Phi (graduated non-convexity, after Yang et
 * al., RA-L 2020). A false link fails the test and DCS switches it off at once. With more
 * than kMaxTested such links (a cold start from dead reckoning: no estimate to test against
 * yet) all of them start graduated. A link the caller vetted against its own, more
 * conservative covariance (`vetted`: the loop closer's gate, which propagates the odometry
 * and scan-match links along one path and so does not let many parallel links of the same
 * corridor shrink the uncertainty of a drift they all share) starts graduated untested. */
constexpr size_t kMaxTested = 32;

bool scheduleLoopLinks(detail::TProblem& prob, const TPoseGraphOptimizerParams& p,
					   CCholmodSolver& solver, detail::TNormalEquations& ne,
					   const std::vector<size_t>& vetted)
{
	const detail::TCostKernel k{true, p.dcs_phi};
	std::vector<size_t> outside;
	std::vector<double> chi2(prob.links.size(), 0.0);
	for (size_t i = 0; i < prob.links.size(); ++i)
	{
		if (!prob.links[i].loopClosure) continue;
		const Eigen::Vector3d e = prob.residual(prob.links[i]);
		chi2[i] = e.dot(prob.links[i].info * e);
		if (k.scale(chi2[i], p.dcs_phi) < p.reject_scale) outside.push_back(i);
	}
	if (outside.empty()) return false;
	prob.linearize(k, ne);
	const bool test = outside.size() <= kMaxTested && solver.factorize(ne, 1e-9);
	bool any = false;
	for (size_t i : outside)
	{
		detail::TProblemLink& l = prob.links[i];
		if (test && std::find(vetted.begin(), vetted.end(), l.id) == vetted.end())
		{
			Eigen::Matrix3d Ji, Jj;
			const Eigen::Vector3d e = prob.residual(l, &Ji, &Jj);
			std::vector<int> idx;
			for (int v : {l.vi, l.vj})
				if (v >= 0)
					for (int r = 0; r < 3; ++r) idx.push_back(3 * v + r);
			Eigen::MatrixXd J(3, idx.size());
			if (l.vi >= 0 && l.vj >= 0)
				J << Ji, Jj;
			else
				J = l.vi >= 0 ? Ji : Jj;
			const Eigen::Matrix3d S = solver.projectedInverse(idx, J) + l.info.inverse();
			if (e.dot(S.ldlt().solve(e)) >= 3 * p.dcs_phi) continue;  // inconsistent
		}
		l.phiStart = chi2[i];
		any = true;
	}
	return any;
}
}  // namespace

struct CPoseGraphOptimizer::Impl
{
	std::mutex mutex;  // one solve at a time uses the CHOLMOD workspace
	CCholmodSolver solver;
};

CPoseGraphOptimizer::CPoseGraphOptimizer(const TPoseGraphOptimizerParams& params)
	: m_params(params), m_impl(std::make_unique<Impl>())
{
}
CPoseGraphOptimizer::~CPoseGraphOptimizer() = default;
CPoseGraphOptimizer::CPoseGraphOptimizer(CPoseGraphOptimizer&&) noexcept = default;
CPoseGraphOptimizer& CPoseGraphOptimizer::operator=(CPoseGraphOptimizer&&) noexcept = default;

TOptimizationReport CPoseGraphOptimizer::solve(detail::TProblem& prob,
											   const std::vector<size_t>& vettedLoopLinks) const
{
	TOptimizationReport rep;
	rep.numFreeNodes = prob.varNode.size();
	rep.numLinks = prob.links.size();
	detail::TCostKernel k{m_params.robust_loop_closures, m_params.dcs_phi};
	rep.initialChi2 = prob.evaluate(prob.x, k, &rep.initialCost);
	std::lock_guard<std::mutex> lock(m_impl->mutex);
	detail::TNormalEquations ne;
	const bool graduated =
		k.robust && scheduleLoopLinks(prob, m_params, m_impl->solver, ne, vettedLoopLinks);
	double maxPhiStart = 0;
	for (const auto& l : prob.links) maxPhiStart = std::max(maxPhiStart, l.phiStart);
	// Stages: the graduated links' Phi shrinks 4x per stage (a few LM iterations each) until
	// every link uses the target Phi; the last stage runs to convergence.
	for (;;)
	{
		const bool last = !graduated || maxPhiStart / k.divisor <= k.phi;
		const int budget = m_params.max_iterations - rep.iterations;
		const TPass pass = levenbergMarquardt(
			prob, k, m_params, last ? m_params.relative_cost_tolerance : 1e-3,
			last ? budget : std::min(5, budget), m_impl->solver, ne, {m_onIteration, m_stop});
		rep.iterations += pass.iterations;
		rep.converged = last && pass.converged;
		rep.stopped = pass.stopped;
		if (last || pass.stopped || rep.iterations >= m_params.max_iterations) break;
		k.divisor *= 4;
	}
	k.divisor = 1e300;  // report against the target Phi
	rep.finalChi2 = prob.evaluate(prob.x, k, &rep.finalCost);
	rep.downweightedLinks = prob.rejectedLoopLinks(k, m_params.reject_scale);
	return rep;
}

TOptimizationReport CPoseGraphOptimizer::optimize(CPoseGraph& g, size_t anchor,
												  const std::vector<size_t>& vettedLoopLinks,
												  size_t frozenBelow) const
{
	const auto t0 = std::chrono::steady_clock::now();
	if (anchor >= g.numNodes())
		THROW_EXCEPTION_FMT(
			"CPoseGraphOptimizer::optimize: anchor %zu out of range (graph has %zu nodes)",
			anchor, g.numNodes());
	detail::TProblem prob = detail::TProblem::wholeGraph(g, anchor, frozenBelow);
	TOptimizationReport rep = solve(prob, vettedLoopLinks);
	prob.writeBack(g);
	rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
	return rep;
}

TOptimizationReport CPoseGraphOptimizer::optimizeSubset(
	CPoseGraph& g, const std::vector<size_t>& freeNodes) const
{
	const auto t0 = std::chrono::steady_clock::now();
	detail::TProblem prob = detail::TProblem::subset(g, freeNodes);
	TOptimizationReport rep = solve(prob);
	prob.writeBack(g);
	rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
	return rep;
}

}  // namespace lrgc
