#include <lrgc/localization/StartFinder.h>

#include <lrgc/common/se2.h>

#include <algorithm>

namespace lrgc
{
CStartFinder::CStartFinder(const CGlobalLocalizer& localizer, const TLRGCParams& params,
						   const TLocalizationParams& localization)
	: m_localizer(localizer), m_params(localization)
{
	TLRGCParams probeParams = params;
	probeParams.builder.loop_closing = false;  // a few metres of log: local registration
	m_probe = std::make_unique<CMetricMapBuilderLRGC>(probeParams);
	m_probe->logging_enable_console_output = false;
}

std::optional<TStartFound> CStartFinder::tryLocate()
{
	const CPoseGraph& g = m_probe->graph();
	const size_t n = g.numNodes();
	if (n < m_nextAttemptAt) return std::nullopt;
	const size_t P = m_params.patch_keyframes;
	m_nextAttemptAt = n < P ? std::min(2 * n, P) : n + std::max<size_t>(1, P / 4);

	// The patch: the newest min(n, P) probe keyframes in the newest one's frame.
	const size_t newest = n - 1, first = n - std::min(n, P);
	const mrpt::math::TPose2D newestInProbe = g.pose(newest);
	std::vector<Eigen::Vector2d> patch;
	for (size_t k = first; k <= newest; ++k)
	{
		const CPointTransform kInNewest(between(newestInProbe, g.pose(k)));
		for (const auto& p : m_probe->keyframes()[k].scan.points)
			if (const Eigen::Vector2d q = kInNewest(p); q.norm() <= m_params.patch_max_range_m)
				patch.push_back(q);
	}
	++m_attempts;
	const TGlobalLocation loc = m_localizer.locate(patch);
	m_seconds += loc.seconds;
	if (!loc.accepted())
	{
		m_lastRejection = loc.stopped ? "stopped" : loc.verdict.message();
		return std::nullopt;
	}
	m_lastRejection.clear();
	TStartFound found;
	found.probeInMap = compose(loc.correlation->patchInMap, inverse(newestInProbe));
	found.cov = loc.correlation->cov;
	found.score = loc.correlation->score;
	found.ambiguity = loc.correlation->ambiguity;
	found.patchKeyframes = newest + 1 - first;
	return found;
}

}  // namespace lrgc
