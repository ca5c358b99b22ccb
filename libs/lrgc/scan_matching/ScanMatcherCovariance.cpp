/* Covariance of a scan match and the truncated Gauss-Newton solve (doc/scan-matching.md).
 *
 * At the optimum sum_i psi(e_i) J_i = 0 (psi(e) = w e, Cauchy). Linearising,
 *   dx = -A^-1 sum_i psi(eps_i) J_i,   A = sum_i psi'(e_i) J_i J_i^T   ("bread"),
 *   Cov(x) = A^-1 M A^-1,              M = Cov(sum_i psi_i J_i)        ("meat").
 * The i.i.d. meat s^2 sum J J^T is over-confident: scan points matched to one stretch of
 * reference wall share that stretch's noise. Two meats are formed and the larger kept (the
 * smallest PSD upper bound of the two resulting covariances):
 *  - model: independent scan noise (variance = the weighted residual variance, conservative)
 *    plus the reference's noise propagated through its line fits
 * (CReferenceCloud::forEachFitTerm), which correlates exactly the residuals that share fit
 * points;
 *  - data: leave-one-cluster-out jackknife over reference cells of side `cluster`,
 *    (G-1)/G sum_g d_g d_g^T with d_g = (A - A_g)^-1 s_g, s_g = sum_{i in g} psi_i J_i, which
 *    catches correlation the model does not know and corrects the leverage of the few clusters
 *    that pin a direction.
 * All in scaled coordinates (tx, ty, L phi), L the RMS lever arm [m], on the observable
 * subspace; unobservable directions (information below s^2 / unobservableStd^2, or less than
 * kSpurious times what the normals' noise alone fakes) get unobservableStd^2.
 */
#include "ScanMatcherDetail.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace lrgc::detail
{
namespace
{
/** Matrices on the observable subspace (1 to 3 dimensions), sized at run time but held
 * without heap allocation: a match's covariance solves one per reference cluster. */
using TMatrixUpTo3 = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3, 3>;
using TVectorUpTo3 = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 3, 1>;

Eigen::Matrix3d scaling(double L)
{
	return Eigen::Vector3d(1, 1, 1 / L).asDiagonal();
}

/** The smallest (PSD order) upper bound of A and B in the form B^1/2 max(I, M) B^1/2 with
 * M = B^-1/2 A B^-T/2, computed on the subspace spanned by the columns of P (orthonormal). */
Eigen::Matrix3d psdMaxOnSubspace(const Eigen::Matrix3d& A, const Eigen::Matrix3d& B,
								 const TMatrixUpTo3& P)
{
	const TMatrixUpTo3 Ao = P.transpose() * A * P, Bo = P.transpose() * B * P;
	const Eigen::LLT<TMatrixUpTo3> llt(Bo);
	if (llt.info() != Eigen::Success) return P * Ao * P.transpose();
	const TMatrixUpTo3 Lb = llt.matrixL();
	const TMatrixUpTo3 Linv = Lb.inverse();
	const TMatrixUpTo3 M = Linv * Ao * Linv.transpose();
	const Eigen::SelfAdjointEigenSolver<TMatrixUpTo3> es(M);
	const TVectorUpTo3 d = es.eigenvalues().cwiseMax(1.0);
	const TMatrixUpTo3 Mmax =
		es.eigenvectors() * d.asDiagonal() * es.eigenvectors().transpose();
	return P * (Lb * Mmax * Lb.transpose()) * P.transpose();
}
/** Covariance of the score sum_i w_i J_i^T e_i under the noise model: independent scan noise
 * (variance s_scan^2 per residual row) and the reference's anchor noise propagated through
 * the line fits (CReferenceCloud::forEachFitTerm), which correlates residuals sharing fit
 * points. */
Eigen::Matrix3d modelScoreCovariance(const CReferenceCloud& ref,
									 const std::vector<TCorrespondence>& corr)
{
	// Per reference point used (a few hundred of a patch's thousands), in order of first use
	// (touched): g_k (LINE fit terms) at slot[k], G_k (POINT anchors) at pointSlot[slot[k]].
	constexpr uint32_t kUnused = ~uint32_t(0);
	std::vector<uint32_t> slot(ref.size(), kUnused);
	std::vector<uint32_t> touched, pointSlot;
	std::vector<Eigen::Vector3d> g;
	std::vector<Eigen::Matrix<double, 3, 2>> G;
	auto use = [&](uint32_t k)
	{
		if (slot[k] == kUnused)
		{
			slot[k] = static_cast<uint32_t>(touched.size());
			touched.push_back(k);
			g.push_back(Eigen::Vector3d::Zero());
			pointSlot.push_back(kUnused);
		}
		return slot[k];
	};
	auto usePoint = [&](uint32_t k)
	{
		const uint32_t s = use(k);
		if (pointSlot[s] == kUnused)
		{
			pointSlot[s] = static_cast<uint32_t>(G.size());
			G.push_back(Eigen::Matrix<double, 3, 2>::Zero());
		}
		return pointSlot[s];
	};
	Eigen::Matrix3d Bscan = Eigen::Matrix3d::Zero();
	double sumW2e2 = 0, sumW2 = 0, rows = 0;
	auto fitTerms = ref.fitTermReader();
	for (const auto& k : corr)
	{
		sumW2e2 += k.w * k.w * k.sqNorm();
		sumW2 += k.w * k.w * (k.isLine ? 1 : 2);
		if (k.isLine)
		{
			Bscan += k.w * k.w * k.J0 * k.J0.transpose();
			rows += 1;
			const double u = ref.anchors()[k.anchor].u + k.tOff;  // line coordinate of q
			fitTerms.forEach(k.anchor,
							 [&](uint32_t point, float b0, float b1)
							 {
								 const double beta = b0 + u * b1;
								 g[use(point)] += k.w * beta * k.J0;
							 });
			continue;
		}
		Bscan += k.w * k.w * (k.J0 * k.J0.transpose() + k.J1 * k.J1.transpose());
		rows += 2;
		const uint32_t a = usePoint(k.anchor);
		G[a].col(0) += k.w * k.J0;
		G[a].col(1) += k.w * k.J1;
	}
	// Scan-side variance per row: the whole (weight^2-averaged, so outliers do not count)
	// residual variance. Part of it is the anchors' own noise, counted again below; the split
	// is not identifiable from one match, and charging it all to the scan is the conservative
	// choice (measured NEES about 2.5 instead of 3.5-4).
	const double s2scan = sumW2 > 0 ? sumW2e2 / sumW2 * rows / std::max(1.0, rows - 3) : 0.0;
	Eigen::Matrix3d B = s2scan * Bscan;
	for (uint32_t s = 0; s < touched.size(); ++s)
	{
		const uint32_t k = touched[s];
		if (pointSlot[s] == kUnused)  // G_k = 0: its terms would add zeros
		{
			// g g^T evaluated first, as in the sum below (a scalar times a bare product would
			// be folded into its factor: other rounding).
			const Eigen::Matrix3d ggT = g[s] * g[s].transpose();
			B += ref.pointVariance(k) * ggT;
			continue;
		}
		const Eigen::Matrix<double, 3, 2>& Gs = G[pointSlot[s]];
		B += ref.pointVariance(k) * (g[s] * g[s].transpose() + Gs * Gs.transpose()) +
			 ref.anchors()[k].samplingVar * Gs * Gs.transpose();
	}
	return B;
}
}  // namespace

TScaledInfo analyseInformation(const Eigen::Matrix3d& H, const Eigen::Matrix3d& Hspurious,
							   double L, double scale, double unobservableStd)
{
	constexpr double kSpurious = 10;
	TScaledInfo I;
	I.L = std::max(L, 1e-3);
	const Eigen::Matrix3d S = scaling(I.L);
	const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(S * H * S);
	I.V = es.eigenvectors();
	I.lambda = es.eigenvalues();
	const double minInfo = scale * scale / (unobservableStd * unobservableStd);
	I.minInfo = minInfo;
	for (int k = 0; k < 3; ++k)
	{
		const double fake = I.V.col(k).dot(S * Hspurious * S * I.V.col(k));
		I.observable[k] = I.lambda[k] >= minInfo && I.lambda[k] > kSpurious * fake;
		I.unobservable += !I.observable[k];
	}
	return I;
}

Eigen::Vector3d solveStep(const TScaledInfo& I, const Eigen::Vector3d& g)
{
	const Eigen::Matrix3d S = scaling(I.L);
	const Eigen::Vector3d gs = S * g;
	Eigen::Vector3d ds = Eigen::Vector3d::Zero();
	for (int k = 0; k < 3; ++k)
		if (I.observable[k]) ds -= I.V.col(k) * (I.V.col(k).dot(gs) / I.lambda[k]);
	return S * ds;
}

namespace
{
/** One spatial cluster of correspondences (anchors in one cluster x cluster cell): its score
 * sum s_g = sum w J^T e and its share M_g of the bread Hpsi. */
struct TCluster
{
	Eigen::Vector3d s = Eigen::Vector3d::Zero();
	Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
};
struct TBread
{
	Eigen::Matrix3d Hpsi = Eigen::Matrix3d::Zero();
	std::unordered_map<uint64_t, TCluster> clusters;
};

/* The bread of the sandwich and its clusters. Cauchy: psi(e) = w e with
 * w = 1 / (1 + |e|^2 / c^2); its derivative is d psi / d e = w I - 2 w^2 e e^T / c^2, i.e.
 * w (1 - 2 w e^2 / c^2) for one row, floored at 0 (PSD). */
TBread breadByCluster(const std::vector<TCorrespondence>& corr, double c, double cluster)
{
	const double c2 = c * c;
	TBread b;
	b.clusters.reserve(corr.size());
	for (const auto& k : corr)
	{
		Eigen::Vector3d s;
		Eigen::Matrix3d Mk;
		if (k.isLine)
		{
			s = k.w * k.e0 * k.J0;
			const double d = k.w * (1 - 2 * k.w * k.e0 * k.e0 / c2);
			Mk = std::max(0.0, d) * k.J0 * k.J0.transpose();
		}
		else
		{
			s = k.w * (k.e0 * k.J0 + k.e1 * k.J1);
			Eigen::Matrix<double, 3, 2> J;
			J << k.J0, k.J1;
			const Eigen::Matrix2d D = cauchyPointBread(k.w, Eigen::Vector2d(k.e0, k.e1), c2);
			Mk = J * D * J.transpose();
		}
		b.Hpsi += Mk;
		const auto ix = static_cast<int64_t>(std::floor(k.anchorPos.x() / cluster));
		const auto iy = static_cast<int64_t>(std::floor(k.anchorPos.y() / cluster));
		const uint64_t key = (static_cast<uint64_t>(static_cast<uint32_t>(ix)) << 32) |
							 static_cast<uint32_t>(iy);
		auto& cl = b.clusters[key];
		cl.s += s;
		cl.M += Mk;
	}
	return b;
}

/** Inverse of the bread on the observable subspace (basis P, scaled by S); where it is not
 * positive definite, the weighted information's, diagonal in that basis. */
TMatrixUpTo3 observableInverse(const TMatrixUpTo3& Ho, const TScaledInfo& I, int nObs)
{
	const Eigen::LLT<TMatrixUpTo3> llt(Ho);
	if (llt.info() == Eigen::Success) return llt.solve(TMatrixUpTo3::Identity(nObs, nObs));
	TMatrixUpTo3 HoInv = TMatrixUpTo3::Zero(nObs, nObs);
	for (int k = 0, j = 0; k < 3; ++k)
		if (I.observable[k]) HoInv(j, j) = 1 / I.lambda[k], ++j;
	return HoInv;
}

/** Leave-one-cluster-out (jackknife) spread: delta_g = (H - M_g)^-1 s_g on the observable
 * subspace, eigenvalues of H - M_g floored at the unobservability threshold; returns
 * sum_g P delta_g delta_g^T P^T (the caller scales by (G - 1) / G). */
Eigen::Matrix3d jackknifeSpread(const TBread& b, const TMatrixUpTo3& Ho, const TMatrixUpTo3& P,
								const Eigen::Matrix3d& S, double minInfo)
{
	Eigen::Matrix3d Csand = Eigen::Matrix3d::Zero();
	const int nObs = static_cast<int>(Ho.rows());
	for (const auto& [key, cl] : b.clusters)
	{
		const TMatrixUpTo3 Hg = Ho - P.transpose() * (S * cl.M * S) * P;
		const TVectorUpTo3 sg = P.transpose() * (S * cl.s);
		// No eigenvalue floored (H_g - minInfo I positive definite: every eigenvalue of H_g
		// above minInfo, the usual case): the floored inverse is H_g^-1, two 3x3 Cholesky
		// factorisations instead of an eigendecomposition per cluster.
		if (nObs == 3)
		{
			const Eigen::Matrix3d Hg3 = Hg;
			const Eigen::LLT<Eigen::Matrix3d> shifted(Hg3 -
													  minInfo * Eigen::Matrix3d::Identity());
			if (shifted.info() == Eigen::Success)
			{
				const Eigen::Vector3d d =
					Eigen::LLT<Eigen::Matrix3d>(Hg3).solve(Eigen::Vector3d(sg));
				Csand += P * (d * d.transpose()) * P.transpose();
				continue;
			}
		}
		const Eigen::SelfAdjointEigenSolver<TMatrixUpTo3> es(Hg);
		const TVectorUpTo3 inv = es.eigenvalues().cwiseMax(minInfo).cwiseInverse();
		const TVectorUpTo3 d =
			es.eigenvectors() * inv.asDiagonal() * es.eigenvectors().transpose() * sg;
		Csand += P * d * d.transpose() * P.transpose();
	}
	return Csand;
}
}  // namespace

Eigen::Matrix2d cauchyPointBread(double w, const Eigen::Vector2d& e, double c2)
{
	const double e2 = e.squaredNorm();
	if (1 - 2 * w * e2 / c2 >= 0)
		return w * Eigen::Matrix2d::Identity() - 2 * w * w / c2 * e * e.transpose();
	return w * (Eigen::Matrix2d::Identity() - e * e.transpose() / e2);
}

// The pose covariance: on the observable subspace the larger (psdMaxOnSubspace) of the model
// sandwich H^-1 B H^-1 and the cluster jackknife's (with more than 3 clusters); along the
// unobservable directions unobservableStd^2 [m^2 / rad^2 in scaled units].
Eigen::Matrix3d poseCovariance(const CReferenceCloud& ref,
							   const std::vector<TCorrespondence>& corr, const TScaledInfo& I,
							   double c, double cluster, double unobservableStd)
{
	const Eigen::Matrix3d Bmodel = modelScoreCovariance(ref, corr);
	const TBread bread = breadByCluster(corr, c, cluster);
	const double G = static_cast<double>(bread.clusters.size());

	const Eigen::Matrix3d S = scaling(I.L);
	int nObs = 0;
	for (int k = 0; k < 3; ++k) nObs += I.observable[k];
	TMatrixUpTo3 P(3, nObs);
	Eigen::Matrix3d Cs = Eigen::Matrix3d::Zero();
	for (int k = 0, j = 0; k < 3; ++k)
	{
		if (I.observable[k])
			P.col(j++) = I.V.col(k);
		else
			Cs += unobservableStd * unobservableStd * I.V.col(k) * I.V.col(k).transpose();
	}
	if (nObs > 0)
	{
		const TMatrixUpTo3 Ho = P.transpose() * (S * bread.Hpsi * S) * P;
		const Eigen::Matrix3d Hinv = P * observableInverse(Ho, I, nObs) * P.transpose();
		const Eigen::Matrix3d Cmodel = Hinv * (S * Bmodel * S) * Hinv;
		Eigen::Matrix3d Csand = jackknifeSpread(bread, Ho, P, S, I.minInfo);
		Csand *= (G - 1) / G;
		Cs += G > 3 ? psdMaxOnSubspace(Csand, Cmodel, P) : Cmodel;
	}
	const Eigen::Matrix3d C = S * Cs * S;
	return 0.5 * (C + C.transpose());
}

}  // namespace lrgc::detail
