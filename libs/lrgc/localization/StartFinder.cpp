#include <lrgc/localization/StartFinder.h>

#include <lrgc/common/se2.h>

#include <algorithm>

namespace lrgc
{
CStartFinder::CStartFinder(const CGlobalLocalizer& localizer, const TLRGCParams& params,
						   const TLocalizationParams& localization, bool backoff)
	: m_localizer(localizer),
	  m_params(localization),
	  m_backoff(backoff),
	  m_spacing(std::max<size_t>(
		  1, backoff ? localization.patch_keyframes : localization.patch_keyframes / 4))
{
	TLRGCParams probeParams = params;
	probeParams.builder.loop_closing = false;  // a few metres of log: local registration
	m_probe = std::make_unique<CMetricMapBuilderLRGC>(probeParams);
	m_probe->logging_enable_console_output = false;
}

std::optional<TStartFound> CStartFinder::tryLocate()
{
	const auto request = nextPatch();
	if (!request) return std::nullopt;
	return conclude(*request, m_localizer.locate(request->points));
}

std::optional<TPatchRequest> CStartFinder::nextPatch()
{
	const CPoseGraph& g = m_probe->graph();
	const size_t n = g.numNodes();
	if (n < m_nextAttemptAt) return std::nullopt;
	const size_t P = m_params.patch_keyframes;
	if (n < P)
		m_nextAttemptAt = std::min(2 * n, P);
	else
	{
		m_nextAttemptAt = n + m_spacing;
		if (m_backoff) m_spacing *= 2;
	}

	// The patch: the newest min(n, P) probe keyframes in the newest one's frame.
	const size_t newest = n - 1, first = n - std::min(n, P);
	TPatchRequest request;
	request.newestInProbe = g.pose(newest);
	request.keyframes = newest + 1 - first;
	for (size_t k = first; k <= newest; ++k)
	{
		const CPointTransform kInNewest(between(request.newestInProbe, g.pose(k)));
		for (const auto& p : m_probe->keyframes()[k].scan.points)
			if (const Eigen::Vector2d q = kInNewest(p); q.norm() <= m_params.patch_max_range_m)
				request.points.push_back(q);
	}
	return request;
}

std::optional<TStartFound> CStartFinder::conclude(const TPatchRequest& request,
												  const TGlobalLocation& loc)
{
	++m_attempts;
	m_seconds += loc.seconds;
	if (!loc.accepted())
	{
		m_lastRejection = loc.stopped ? "stopped" : loc.verdict.message();
		return std::nullopt;
	}
	m_lastRejection.clear();
	TStartFound found;
	found.probeInMap = compose(loc.correlation->patchInMap, inverse(request.newestInProbe));
	found.cov = loc.correlation->cov;
	found.score = loc.correlation->score;
	found.ambiguity = loc.correlation->ambiguity;
	found.patchKeyframes = request.keyframes;
	return found;
}

}  // namespace lrgc
