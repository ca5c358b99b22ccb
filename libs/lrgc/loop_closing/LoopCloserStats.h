/* What loop closing reports (stats.json "loop_closing", logs): a product of the map builder,
 * apart from CLoopCloser so that the builder's public header needs none of its internals. */
#pragma once

#include <cstddef>
#include <vector>

namespace lrgc
{
/** Counters for logs and stats. */
struct TLoopCloserStats
{
	size_t attempts = 0;  //!< correlations run
	size_t accepted = 0;  //!< links added
	size_t rejectedByFilters = 0, rejectedByMatch = 0, rejectedByBackEnd = 0;
	/** Matches held until a later, independent one agrees (the gate's std above
	 * [LoopCloser] confirm_above_sigma), and those dropped because the next disagreed or
	 * none came. */
	size_t heldForConfirmation = 0, unconfirmed = 0;
	size_t optimizations = 0;
	std::vector<double> closureSeconds;  //!< per optimised closure
};

}  // namespace lrgc
