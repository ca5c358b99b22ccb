/* Dijkstra propagation of first-order relative pose covariance over the pose graph (see
 * UncertaintyPropagation.h for the method and what it approximates). */
#include <lrgc/loop_closing/UncertaintyPropagation.h>

#include <mrpt/core/exceptions.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <functional>
#include <queue>
#include <limits>

#include <lrgc/common/se2.h>

namespace lrgc
{
namespace
{
struct TLabel
{
	Eigen::Matrix3d cov;
	double key = std::numeric_limits<double>::infinity();  // trace of the xy block [m^2]
	bool settled = false;
};

double positionVariance(const Eigen::Matrix3d& c)
{
	return c(0, 0) + c(1, 1);
}

/** Covariance of (source <- v) = (source <- u) (+) (u <- v), first order; c, s are
 * cos, sin of (source <- u).phi (the same for every link of u), (x, y) the position of v in
 * u's frame [m]. */
Eigen::Matrix3d compound(double c, double s, const Eigen::Matrix3d& covU, double x, double y,
						 const Eigen::Matrix3d& covUV)
{
	Eigen::Matrix3d J1 = Eigen::Matrix3d::Identity(), J2 = Eigen::Matrix3d::Identity();
	J1(0, 2) = -(s * x + c * y);
	J1(1, 2) = c * x - s * y;
	J2(0, 0) = c, J2(0, 1) = -s, J2(1, 0) = s, J2(1, 1) = c;
	return J1 * covU * J1.transpose() + J2 * covUV * J2.transpose();
}
}  // namespace

TRelativeUncertainty chainUncertainty(const TRelativeUncertainty& aInSource,
									  const TRelativeUncertainty& vInA)
{
	const TPose2D& a = aInSource.nodeInSource;
	const TPose2D& v = vInA.nodeInSource;
	return {vInA.node, compose(a, v),
			compound(std::cos(a.phi), std::sin(a.phi), aInSource.cov, v.x, v.y, vInA.cov)};
}

Eigen::Matrix3d inverseCovariance(const TPose2D& z, const Eigen::Matrix3d& covZ)
{
	const double c = std::cos(z.phi), s = std::sin(z.phi);
	Eigen::Matrix3d J;
	J << -c, -s, s * z.x - c * z.y,  //
		s, -c, c * z.x + s * z.y,    //
		0, 0, -1;
	return J * covZ * J.transpose();
}

namespace
{
struct TStep
{
	size_t v;
	LinkType type;
	Eigen::Matrix3d covUV;
};
using TSteps = std::vector<std::pair<size_t, Eigen::Matrix3d>>;

/** The steps from u to its unsettled neighbours v, as (v, covariance of (u <- v)) in `out`:
 * every link a step of its own, or (model.fuseParallelLinks) one step per neighbour with the
 * information of its links added across types, the link most certain in position standing for
 * each type. `steps` and `out` are reused from node to node (no allocation once grown). */
void stepsFrom(const CPoseGraph& g, size_t u, const std::vector<TLabel>& labels,
			   const TStepModel& model, std::vector<TStep>& steps, TSteps& out)
{
	steps.clear();
	out.clear();
	const TPose2D& uInMap = g.pose(u);
	for (size_t id : g.linksOf(u))
	{
		if (!g.isLinkEnabled(id)) continue;
		const TLink& l = g.link(id);
		const size_t v = l.from == u ? l.to : l.from;
		if (labels[v].settled) continue;
		const Eigen::Matrix3d covLink = l.information.inverse();
		const Eigen::Matrix3d covUV =
			l.from == u ? covLink : inverseCovariance(between(g.pose(v), uInMap), covLink);
		if (!model.fuseParallelLinks)
		{
			out.emplace_back(v, covUV);  // every link a step of its own
			continue;
		}
		auto same = std::find_if(steps.begin(), steps.end(),
								 [&](const TStep& s) { return s.v == v && s.type == l.type; });
		if (same == steps.end())
			steps.push_back({v, l.type, covUV});
		else if (positionVariance(covUV) < positionVariance(same->covUV))
			same->covUV = covUV;
	}
	for (size_t i = 0; i < steps.size(); ++i)
	{
		const size_t v = steps[i].v;
		if (std::any_of(steps.begin(), steps.begin() + i,
						[&](const TStep& s) { return s.v == v; }))
			continue;  // fused with an earlier one
		Eigen::Matrix3d info = Eigen::Matrix3d::Zero();
		size_t types = 0;
		for (size_t j = i; j < steps.size(); ++j)
			if (steps[j].v == v)
			{
				info += steps[j].covUV.inverse();
				++types;
			}
		out.emplace_back(v, types == 1 ? steps[i].covUV : Eigen::Matrix3d(info.inverse()));
	}
}
}  // namespace

std::vector<TRelativeUncertainty> propagateUncertainty(const CPoseGraph& g, size_t source,
													   const TUncertaintyLimits& limits,
													   const TStepModel& model)
{
	if (source >= g.numNodes())
		THROW_EXCEPTION_FMT(
			"propagateUncertainty: source node %zu out of range (graph has %zu nodes)", source,
			g.numNodes());
	ASSERT_(limits.maxPositionStd >= 0);
	const double maxVar = limits.maxPositionStd * limits.maxPositionStd;
	const TPose2D& sourceInMap = g.pose(source);

	// Labels indexed by node: a flat array is much cheaper than a hash map when the search
	// reaches most of the graph, as it does once loops have shrunk the uncertainty.
	std::vector<TLabel> labels(g.numNodes());
	using QItem = std::pair<double, size_t>;
	std::priority_queue<QItem, std::vector<QItem>, std::greater<QItem>> queue;
	labels[source] = {Eigen::Matrix3d::Zero(), 0.0};
	queue.push({0.0, source});

	std::vector<TRelativeUncertainty> out;
	std::vector<TStep> stepScratch;
	TSteps steps;
	while (!queue.empty())
	{
		const auto [key, u] = queue.top();
		queue.pop();
		TLabel& lu = labels[u];
		if (lu.settled || key > lu.key) continue;  // stale entry
		lu.settled = true;
		const TPose2D uInSource = between(sourceInMap, g.pose(u));
		out.push_back({u, uInSource, lu.cov});
		if ((limits.maxNodes && out.size() >= limits.maxNodes) || u == limits.stopAtNode) break;
		if (lu.key > maxVar) continue;  // returned, not expanded
		// The trigonometry of u's frame and of (source <- u), shared by all of u's links.
		const TPose2D& uInMap = g.pose(u);
		const double cu = std::cos(uInMap.phi), su = std::sin(uInMap.phi);
		const double cs = std::cos(uInSource.phi), ss = std::sin(uInSource.phi);
		const Eigen::Matrix3d& covU = lu.cov;
		stepsFrom(g, u, labels, model, stepScratch, steps);
		for (auto& [v, covUV] : steps)
		{
			// Linearise at the current estimate of the step's relative pose: v's position in
			// u's frame, between(pose(u), pose(v)), with u's cos/sin computed once.
			const TPose2D& vInMap = g.pose(v);
			const double dx = vInMap.x - uInMap.x, dy = vInMap.y - uInMap.y;
			if (model.driftXY > 0)
			{
				const double drift = model.driftXY * std::hypot(dx, dy);  // [m^2]
				covUV(0, 0) += drift, covUV(1, 1) += drift;
			}
			const Eigen::Matrix3d covV =
				compound(cs, ss, covU, cu * dx + su * dy, -su * dx + cu * dy, covUV);
			const double keyV = positionVariance(covV);
			TLabel& lv = labels[v];
			if (keyV >= lv.key) continue;  // unreached nodes have key +inf
			lv.cov = covV;
			lv.key = keyV;
			queue.push({keyV, v});
		}
	}
	return out;
}

double positionMahalanobis2(const TRelativeUncertainty& r)
{
	const Eigen::Vector2d d(r.nodeInSource.x, r.nodeInSource.y);
	if (d.squaredNorm() == 0) return 0.0;
	const Eigen::LDLT<Eigen::Matrix2d> ldlt(r.cov.topLeftCorner<2, 2>());
	if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().array() > 0).all())
		THROW_EXCEPTION_FMT("positionMahalanobis2: position covariance of node %zu is singular",
							r.node);
	return d.dot(ldlt.solve(d));
}

}  // namespace lrgc
