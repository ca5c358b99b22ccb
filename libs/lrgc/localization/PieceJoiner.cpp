#include <lrgc/localization/PieceJoiner.h>

#include <lrgc/common/se2.h>

#include <algorithm>

namespace lrgc
{
CPieceJoiner::CPieceJoiner(const CPoseGraph& map, const TKeyframes& keyframes,
						   const TPatchCorrelatorParams& correlator,
						   const TLocalizationParams& localization, bool backgroundSearch)
	: m_params(localization),
	  m_global(map, keyframes, correlator),
	  m_worker(m_global, localization.search_budget_ms_per_s, backgroundSearch),
	  m_schedule(localization.patch_keyframes, false)
{
}

std::optional<TPieceJoin> CPieceJoiner::service(const CMetricMapBuilderLRGC& builder,
												double now)
{
	const std::optional<size_t> first = builder.pieceFirstNode();
	ASSERTMSG_(first, "CPieceJoiner::service: the builder maps no piece apart");
	m_logClock = std::max(m_logClock, now);
	if (auto location = m_worker.takeIfDue(m_logClock))
		if (auto join = conclude(*location))
		{
			// The scan check: a join the patch's own scans do not confirm is refused, and the
			// search goes on (SENA seen in a mirror joined SENA's map by the grid alone).
			const std::string problem = patchProblem(builder, *join);
			if (problem.empty()) return join;
			++m_refusedByScan;
			m_lastRejection = "the scan check: " + problem;
		}
	const CPoseGraph& g = builder.graph();
	const size_t n = g.numNodes() - *first;  // the piece's keyframes
	if (m_worker.busy() || n == 0 || !m_schedule.due(n)) return std::nullopt;
	const size_t newest = g.numNodes() - 1;
	m_inFlight = patchOfKeyframes(g, builder.keyframes(),
								  newest + 1 - std::min(n, m_params.patch_keyframes), newest,
								  m_params.patch_max_range_m);
	m_inFlightNode = newest;
	TGlobalSearchJob job;
	job.patch = m_inFlight->points;
	job.area = m_global.wholeMap();
	job.submittedAt = m_logClock;
	m_worker.submit(std::move(job));
	return std::nullopt;
}

// Each keyframe of the accepted patch (the piece's keyframes join.node - patchKeyframes + 1 ..
// join.node), placed by the join, must be confirmed by its scan match with the map around it,
// as a localisation's start is (CLocalizer::probeMatchesMap, which says why every one): ACES
// continued on MIT-CSAIL's map joined it after 7177 scans with the newest keyframe's check
// alone.
std::string CPieceJoiner::patchProblem(const CMetricMapBuilderLRGC& builder,
									   const TPieceJoin& join) const
{
	const CPoseGraph& g = builder.graph();
	const size_t first = *builder.pieceFirstNode();
	const size_t count =
		std::min(join.node + 1 - first, std::max<size_t>(1, join.patchKeyframes));
	for (size_t k = join.node + 1 - count; k <= join.node; ++k)
	{
		const mrpt::math::TPose2D kInMap =
			compose(join.nodeInMap, between(g.pose(join.node), g.pose(k)));
		if (auto problem = builder.pieceJoinProblem(k, kInMap, join.cov); !problem.empty())
			return mrpt::format("keyframe %zu of the patch: %s", k, problem.c_str());
	}
	return {};
}

// The patch is in its newest keyframe's frame: the correlation's (map <- patch) is that
// keyframe's map pose.
std::optional<TPieceJoin> CPieceJoiner::conclude(const TGlobalLocation& location)
{
	++m_attempts;
	m_seconds += location.seconds;
	const TPatchRequest request = std::move(*m_inFlight);
	m_inFlight.reset();
	if (!location.accepted())
	{
		m_lastRejection = location.stopped ? "stopped" : location.verdict.message();
		return std::nullopt;
	}
	m_lastRejection.clear();
	TPieceJoin join;
	join.node = m_inFlightNode;
	join.nodeInMap = location.correlation->patchInMap;
	join.cov = location.correlation->cov;
	join.score = location.correlation->score;
	join.ambiguity = location.correlation->ambiguity;
	join.patchKeyframes = request.keyframes;
	return join;
}

}  // namespace lrgc
