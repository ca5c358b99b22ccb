#include <lrgc/localization/StartFinder.h>

#include <lrgc/common/se2.h>

#include <algorithm>

namespace lrgc
{
TPatchRequest patchOfKeyframes(const CPoseGraph& g, const TKeyframes& keyframes, size_t first,
							   size_t newest, double maxRange)
{
	TPatchRequest request;
	request.newestInProbe = g.pose(newest);
	request.keyframes = newest + 1 - first;
	for (size_t k = first; k <= newest; ++k)
	{
		const CPointTransform kInNewest(between(request.newestInProbe, g.pose(k)));
		for (const auto& p : keyframes[k].scan.points)
			if (const Eigen::Vector2d q = kInNewest(p); q.norm() <= maxRange)
				request.points.push_back(q);
	}
	return request;
}

CPatchSchedule::CPatchSchedule(size_t patchKeyframes, bool backoff)
	: m_patch(patchKeyframes),
	  m_backoff(backoff),
	  m_spacing(std::max<size_t>(1, backoff ? patchKeyframes : patchKeyframes / 4))
{
}

bool CPatchSchedule::due(size_t n)
{
	if (n < m_nextAttemptAt) return false;
	if (n < m_patch)
		m_nextAttemptAt = std::min(2 * n, m_patch);
	else
	{
		m_nextAttemptAt = n + m_spacing;
		if (m_backoff) m_spacing *= 2;
	}
	return true;
}

CStartFinder::CStartFinder(const CGlobalLocalizer& localizer, const TLRGCParams& params,
						   const TLocalizationParams& localization, bool backoff)
	: m_localizer(localizer),
	  m_params(localization),
	  m_schedule(localization.patch_keyframes, backoff)
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

// The patch: the newest min(n, P) probe keyframes in the newest one's frame.
std::optional<TPatchRequest> CStartFinder::nextPatch()
{
	const CPoseGraph& g = m_probe->graph();
	const size_t n = g.numNodes();
	if (!m_schedule.due(n)) return std::nullopt;
	return patchOfKeyframes(g, m_probe->keyframes(), n - std::min(n, m_params.patch_keyframes),
							n - 1, m_params.patch_max_range_m);
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
