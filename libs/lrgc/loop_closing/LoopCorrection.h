/* The one rule by which a loop result's correction reaches the poses it did not place.
 *
 * A loop search for keyframe k runs on the graph as it was when k was handed over; its result
 * places nodes firstMoved..k. Nodes added after k, and the robot, were registered against the
 * old estimate and are carried along rigidly by node k's correction (no re-registration):
 *     X_i <- X'_k (+) (X_k^-1 (+) X_i)
 * X_k, X_i: the poses before the correction [map frame]; X'_k: node k's corrected pose. Both
 * threads apply it: the mapping thread to its graph (CLoopClosing), the worker to the poses a
 * later job sent before the correction reached the mapping thread (CLoopClosingWorker). */
#pragma once

#include <lrgc/common/se2.h>

namespace lrgc
{
/** X_i carried along by the correction of X_k to X'_k (see above). */
inline mrpt::math::TPose2D carriedAlong(const mrpt::math::TPose2D& oldK,
										const mrpt::math::TPose2D& newK,
										const mrpt::math::TPose2D& x)
{
	return compose(newK, between(oldK, x));
}

}  // namespace lrgc
