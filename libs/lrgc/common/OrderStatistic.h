/* Order statistics of a sample, in place, for the stages' robust scales and medians (MAD
 * scales, median noise estimates, median spacings): the k-th smallest value by
 * std::nth_element, O(n) on average. The sample's order is changed. */
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace lrgc
{
/** The k-th smallest value of v (0-based; k < v.size()). Reorders v. */
template <class T>
T kthSmallest(std::vector<T>& v, size_t k)
{
	const auto it = v.begin() + static_cast<std::ptrdiff_t>(k);
	std::nth_element(v.begin(), it, v.end());
	return *it;
}

/** The upper median of v, its (n / 2)-th smallest value: the median for an odd n, the upper
 * of the two middle values for an even n. v must not be empty. Reorders v. */
template <class T>
T upperMedian(std::vector<T>& v)
{
	return kthSmallest(v, v.size() / 2);
}
}  // namespace lrgc
