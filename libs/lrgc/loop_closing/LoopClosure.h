/* One accepted loop closure (CLoopCloser::process), as the map builder reports it. */
#pragma once

#include <cstddef>

namespace lrgc
{
struct TLoopClosure
{
	size_t oldNode = 0, newNode = 0;
	size_t linkId = 0;
	double score = 0, ambiguity = 0;  //!< of the correlation
	bool optimized = false;           //!< the link moved the map: whole graph optimised
	size_t rematchLinks = 0;          //!< links added by re-matching after the closure
	double seconds = 0;               //!< time of the whole closure step [s]
};

}  // namespace lrgc
