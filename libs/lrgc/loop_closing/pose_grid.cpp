#include "pose_grid.h"

#include "correlation_search.h"

#include <algorithm>
#include <cmath>

namespace lrgc::detail
{
void appendBaseCells(const CCorrelationGrid& grid, const std::vector<Eigen::Vector2d>& pts,
					 const mrpt::math::TPose2D& center, double theta, std::vector<int32_t>& out)
{
	const double c = std::cos(theta), s = std::sin(theta);
	for (const auto& p : pts)
	{
		const Eigen::Vector2i cell =
			grid.cellOf({center.x + c * p.x() - s * p.y(), center.y + s * p.x() + c * p.y()});
		out.push_back(cell.x());
		out.push_back(cell.y());
	}
}

namespace
{
// Weighted covariance of the response sampled on the lattice (u strideXY, v strideXY,
// t strideTh) around (a, i, j), |u|, |v| <= nXY, |t| <= nTh; plus the lattice's own
// discretisation step^2 / 12.
Eigen::Matrix3d sampledCovariance(const TPatchCorrelatorParams& prm,
								  const CCorrelationGrid& grid,
								  const std::vector<Eigen::Vector2d>& pts,
								  const TGridSpec& spec, int a, int i, int j, int64_t bestScore,
								  int strideXY, int nXY, int strideTh, int nTh)
{
	TPoseGridProblem local;
	local.grid = &grid;
	local.numPoints = static_cast<int>(pts.size());
	local.numAngles = 2 * nTh + 1;
	for (int t = -nTh; t <= nTh; ++t)
		appendBaseCells(grid, pts, spec.center, spec.theta(a) + t * strideTh * spec.dtheta,
						local.baseCells);
	// scoreLattice reads the base cells alone: no prepare() (bounding boxes, linear offsets).
	const double scale = prm.cluster_score_scale * double(std::max<int64_t>(bestScore, 1));
	const double qXY = strideXY * spec.res, qTh = strideTh * spec.dtheta;
	double wsum = 0;
	Eigen::Vector3d m1 = Eigen::Vector3d::Zero();
	Eigen::Matrix3d m2 = Eigen::Matrix3d::Zero();
	const size_t side = size_t(2 * nXY + 1);
	std::vector<int64_t> scores;
	for (int t = -nTh; t <= nTh; ++t)
	{
		detail::scoreLattice(local, t + nTh, i, j, strideXY, nXY, scores);
		for (int u = -nXY; u <= nXY; ++u)
			for (int v = -nXY; v <= nXY; ++v)
			{
				const int64_t s = scores[size_t(u + nXY) * side + size_t(v + nXY)];
				const double w = std::exp(double(s - bestScore) / scale);
				const Eigen::Vector3d d(u * qXY, v * qXY, t * qTh);
				wsum += w;
				m1 += w * d;
				m2 += w * d * d.transpose();
			}
	}
	m1 /= wsum;
	Eigen::Matrix3d cov = m2 / wsum - m1 * m1.transpose();
	cov.diagonal() += Eigen::Vector3d(qXY * qXY, qXY * qXY, qTh * qTh) / 12.0;
	return cov;
}
}  // namespace

Eigen::Matrix3d clusterCovariance(const TPatchCorrelatorParams& prm,
								  const CCorrelationGrid& grid,
								  const std::vector<Eigen::Vector2d>& pts,
								  const TGridSpec& spec, int a, int i, int j, int64_t bestScore)
{
	constexpr int kFine = 4;
	const Eigen::Matrix3d fine =
		sampledCovariance(prm, grid, pts, spec, a, i, j, bestScore, 1, kFine, 1, kFine);
	const double lim2XY = std::pow(kFine * spec.res / 3, 2);
	const double lim2Th = std::pow(kFine * spec.dtheta / 3, 2);
	if (fine(0, 0) <= lim2XY && fine(1, 1) <= lim2XY && fine(2, 2) <= lim2Th) return fine;
	const double boxXY = 3 * prm.max_std_xy_m, boxTh = 3 * prm.max_std_phi;
	const int strideXY = std::max(1, int(std::ceil(boxXY / spec.res / kFine)));
	const int strideTh = std::max(1, int(std::ceil(boxTh / spec.dtheta / kFine)));
	const int nXY = std::max(1, int(std::floor(boxXY / (strideXY * spec.res))));
	const int nTh = std::max(1, int(std::floor(boxTh / (strideTh * spec.dtheta))));
	const Eigen::Matrix3d coarse =
		sampledCovariance(prm, grid, pts, spec, a, i, j, bestScore, strideXY,
						  std::min(kFine, nXY), strideTh, std::min(kFine, nTh));
	// Keep the finer estimate of any axis that the fine lattice did contain.
	Eigen::Matrix3d out = coarse;
	for (int k = 0; k < 3; ++k)
		if (fine(k, k) <= (k < 2 ? lim2XY : lim2Th) && fine(k, k) < coarse(k, k))
		{
			const double f = std::sqrt(fine(k, k) / coarse(k, k));
			out.row(k) *= f;
			out.col(k) *= f;
		}
	return out;
}

}  // namespace lrgc::detail
