#include <lrgc/common/OrderStatistic.h>

#include <gtest/gtest.h>

namespace lrgc
{
TEST(OrderStatistic, KthSmallestIsTheValueASortWouldPutAtK)
{
	const std::vector<double> sample{5.0, -1.0, 3.0, 3.0, 8.0, 0.5, 2.0};
	std::vector<double> sorted = sample;
	std::sort(sorted.begin(), sorted.end());
	for (size_t k = 0; k < sample.size(); ++k)
	{
		std::vector<double> v = sample;
		EXPECT_EQ(kthSmallest(v, k), sorted[k]) << "k = " << k;
	}
}

TEST(OrderStatistic, UpperMedianOfOddAndEvenSamples)
{
	std::vector<double> odd{9.0, 1.0, 4.0};
	EXPECT_EQ(upperMedian(odd), 4.0);
	std::vector<double> even{4.0, 1.0, 3.0, 2.0};
	EXPECT_EQ(upperMedian(even), 3.0);  // the upper of the middle two, 2 and 3
	std::vector<float> one{7.0f};
	EXPECT_EQ(upperMedian(one), 7.0f);
}
}  // namespace lrgc
