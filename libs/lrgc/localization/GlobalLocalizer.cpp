#include <lrgc/localization/GlobalLocalizer.h>

#include <lrgc/common/se2.h>
#include <lrgc/loop_closing/LoopWork.h>

#include <mrpt/core/exceptions.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace lrgc
{
CGlobalLocalizer::CGlobalLocalizer(const CPoseGraph& map, const TKeyframes& keyframes,
								   const TPatchCorrelatorParams& p)
	: m_correlator(p)
{
	ASSERTMSG_(map.numNodes() > 0, "CGlobalLocalizer: the map has no keyframe");
	ASSERT_EQUAL_(map.numNodes(), keyframes.size());
	std::vector<Eigen::Vector2d> points;
	Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e18), hi = -lo;
	for (size_t i = 0; i < map.numNodes(); ++i)
	{
		const mrpt::math::TPose2D& robotInMap = map.pose(i);
		lo = lo.cwiseMin(Eigen::Vector2d(robotInMap.x, robotInMap.y));
		hi = hi.cwiseMax(Eigen::Vector2d(robotInMap.x, robotInMap.y));
		const CPointTransform toMap(robotInMap);
		for (const auto& q : keyframes[i].scan.points) points.push_back(toMap(q));
	}
	ASSERTMSG_(!points.empty(), "CGlobalLocalizer: the map's scans hold no point");
	try
	{
		m_grid = m_correlator.makeGrid(points, 3 * p.blur_sigma_m);
	}
	catch (const std::exception&)
	{
		// A map wider than the correlation grid's cell budget (2^28 cells in CCorrelationGrid:
		// about 820 x 820 m at 5 cm) gets a message a user can act on; anything else as it is.
		Eigen::Vector2d plo = points.front(), phi = plo;
		for (const auto& q : points) plo = plo.cwiseMin(q), phi = phi.cwiseMax(q);
		const Eigen::Vector2d cells = (phi - plo) / p.resolution_m;
		if (!(cells.x() * cells.y() > 2.5e8)) throw;
		THROW_EXCEPTION_FMT(
			"the map's scans span %.4g x %.4g m: too large to search whole for the log's start "
			"at [PatchCorrelator] resolution_m = %g (a grid of at most about %.0f x %.0f m); a "
			"coarser resolution (--config) covers more",
			phi.x() - plo.x(), phi.y() - plo.y(), p.resolution_m, 16384 * p.resolution_m,
			16384 * p.resolution_m);
	}
	const Eigen::Vector2d c = 0.5 * (lo + hi);
	m_whole.centre = mrpt::math::TPose2D(c.x(), c.y(), 0);
	m_whole.halfXY = 0.5 * (hi - lo).maxCoeff() + kWindowMargin;
	m_whole.halfTheta = M_PI;
}

TSearchArea CGlobalLocalizer::clipped(const TSearchArea& area) const
{
	// A square window that holds the whole map's square searches the whole map's positions.
	TSearchArea out = area;
	out.halfTheta = std::min(area.halfTheta, M_PI);
	const double reach = std::max(std::abs(area.centre.x - m_whole.centre.x),
								  std::abs(area.centre.y - m_whole.centre.y)) +
						 m_whole.halfXY;
	if (area.halfXY >= reach)
	{
		out.centre.x = m_whole.centre.x, out.centre.y = m_whole.centre.y;
		out.halfXY = m_whole.halfXY;
	}
	return out;
}

// Work counted as TLoopWork counts a loop search's correlation (LoopWork.h).
static double modelledCorrelationMs(const TCorrelationEffort& e)
{
	TLoopWork w;
	w.correlations = 1;
	w.correlationAngleCells = double(e.headings) * double(e.patchCells);
	w.correlationPoseCells = double(e.posesScored) * double(e.patchCells);
	return w.referenceMs();
}

TGlobalLocation CGlobalLocalizer::locate(const std::vector<Eigen::Vector2d>& patchPoints,
										 const TSearchArea& area,
										 const TWorkProgress& progress) const
{
	const auto t0 = std::chrono::steady_clock::now();
	TGlobalLocation out;
	TCorrelationEffort effort;
	double published = 0;
	if (progress)
		effort.onProgress = [&](const TCorrelationEffort& e)
		{
			published = std::max(published, modelledCorrelationMs(e));
			progress(published);
		};
	out.correlation = m_correlator.correlate(m_grid, patchPoints, area.centre, area.halfXY,
											 area.halfTheta, &effort);
	out.modelledMs = std::max(published, modelledCorrelationMs(effort));
	out.stopped = !out.correlation && m_correlator.stopToken().stopRequested();
	out.verdict = out.correlation ? out.correlation->checkFilters(m_correlator.params())
								  : TCorrelationVerdict{TCorrelationVerdict::Reason::LowScore,
														0, m_correlator.params().min_score};
	out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
	return out;
}

}  // namespace lrgc
