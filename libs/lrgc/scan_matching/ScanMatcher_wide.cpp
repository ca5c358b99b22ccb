/* CScanMatcher's wide search (matchWide, ScanMatcher.h): match() started from headings across
 * the search angle, each converged start a hypothesis scored by the share of the scan it
 * explains, the winner accepted only with a clear lead over every distinct rival and over the
 * guess's own optimum. The local match itself: ScanMatcher.cpp. */
#include <lrgc/scan_matching/ScanMatcher.h>
#include <lrgc/common/se2.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/math/wrap2pi.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <vector>

#include "ScanMatcherDetail.h"

namespace lrgc
{
namespace
{
/** Points of the scan matchWide explores each start heading with [points]: enough to fix a
 * pose on two walls, few enough for ~25 starts in a few ms. */
constexpr size_t kWideSearchSample = 120;

/** Share of the points `pts` (scan frame) lying within `tol` [m] of a reference anchor at
 * pose x (ref <- scan). matchWide compares hypotheses by it: a match's own inlier fraction
 * counts residuals within a few of *its* residual scales, which a wrong fit inflates. */
double explainedFractionOf(const CReferenceCloud& ref, const std::vector<Eigen::Vector2d>& pts,
						   const mrpt::math::TPose2D& x, double tol)
{
	if (pts.empty()) return 0;
	const CPointTransform toRef(x);
	size_t n = 0;
	for (const auto& p : pts) n += ref.nearest(toRef(p), tol) >= 0;
	return static_cast<double>(n) / pts.size();
}
}  // namespace

bool CScanMatcher::distinctHypotheses(const mrpt::math::TPose2D& a,
									  const mrpt::math::TPose2D& b)
{
	const auto d = between(a, b);
	return translationNorm(d) > 0.2 || std::abs(d.phi) > 3 * M_PI / 180;
}

double CScanMatcher::explainedFraction(const CReferenceCloud& ref, const TScan2D& scan,
									   const mrpt::math::TPose2D& scanInRef) const
{
	return explainedFractionOf(ref, scan.points, scanInRef, m_params.max_rms_residual_m);
}

std::optional<TScanMatch> CScanMatcher::matchWide(const CReferenceCloud& ref,
												  const TScan2D& scan,
												  const mrpt::math::TPose2D& guess,
												  double searchAngle,
												  const TParallelFor& parallel, double stepArg,
												  double* sharedHeading) const
{
	if (sharedHeading) *sharedHeading = std::numeric_limits<double>::quiet_NaN();
	ASSERT_(searchAngle >= 0 && stepArg >= 0);
	const double step = stepArg > 0 ? stepArg : m_params.wide_search_step;
	const double margin = m_params.wide_ambiguity_margin;
	// Every hypothesis is scored alike: the share of points within the largest inlier RMS a
	// match may have (max_rms_residual_m [m]) of the reference.
	const double tol = m_params.max_rms_residual_m;
	const auto distinct = &CScanMatcher::distinctHypotheses;
	// Explore with at most ~kWideSearchSample evenly spread points and a doubled gate, every
	// converged start counting as a hypothesis whether match() would accept it or not (an
	// aliased twin that fails the free-space test is still a twin).
	const size_t stride = std::max<size_t>(1, scan.points.size() / kWideSearchSample);
	std::vector<Eigen::Vector2d> sub;
	for (size_t i = 0; i < scan.points.size(); i += stride) sub.push_back(scan.points[i]);
	const int n = static_cast<int>(std::floor(searchAngle / step + 1e-9));
	// Start i explores heading guess.phi + (i - n) step; kept in start order.
	std::vector<std::optional<std::pair<double, mrpt::math::TPose2D>>> starts(2 * n + 1);
	const std::function<void(size_t)> explore = [&](size_t i)
	{
		if (m_stop.stopRequested()) return;
		mrpt::math::TPose2D g = guess;
		g.phi = mrpt::math::wrapToPi(guess.phi + (static_cast<int>(i) - n) * step);
		if (auto m = matchPoints(ref, sub, g, 2 * m_params.max_correspondence_dist_m))
			starts[i] = {explainedFractionOf(ref, sub, m->scanInRef, tol), m->scanInRef};
	};
	if (parallel)
		parallel(starts.size(), explore);
	else
		for (size_t i = 0; i < starts.size(); ++i) explore(i);
	if (m_stop.stopRequested()) return std::nullopt;            // some starts were not explored
	std::vector<std::pair<double, mrpt::math::TPose2D>> found;  // (score, ref <- scan)
	for (const auto& s : starts)
		if (s) found.push_back(*s);
	if (found.empty()) return std::nullopt;
	std::sort(found.begin(), found.end(),
			  [](const auto& a, const auto& b) { return a.first > b.first; });
	const auto& [bestScore, bestPose] = found.front();
	bool rivalled = false, otherHeading = false;
	for (size_t i = 1; i < found.size(); ++i)
		if (distinct(bestPose, found[i].second) && bestScore - found[i].first < margin)
			rivalled = true,
			otherHeading |=
				std::abs(mrpt::math::wrapToPi(found[i].second.phi - bestPose.phi)) > step / 2;
	if (rivalled)
	{
		if (sharedHeading && !otherHeading) *sharedHeading = bestPose.phi;
		return std::nullopt;
	}
	// Refine the winner with the whole scan, match()'s checks applying, and ask for a clear
	// majority of the scan matched.
	auto won =
		matchPoints(ref, scan.points, bestPose, m_params.max_correspondence_dist_m, &scan);
	if (!won || won->inlierFraction < m_params.wide_min_inlier_fraction) return std::nullopt;
	// The guess's own hypothesis on the same footing (whole scan, plain gate, unchecked): the
	// winner must explain clearly more of the scan than the guess's local optimum does.
	if (const auto atGuess =
			matchPoints(ref, scan.points, guess, m_params.max_correspondence_dist_m);
		atGuess && distinct(won->scanInRef, atGuess->scanInRef) &&
		explainedFractionOf(ref, scan.points, won->scanInRef, tol) -
				explainedFractionOf(ref, scan.points, atGuess->scanInRef, tol) <
			margin)
		return std::nullopt;
	return won;
}

}  // namespace lrgc
