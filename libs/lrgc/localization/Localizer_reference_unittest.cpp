/* CLocalizer::stillCovers, the rule that keeps the tracking reference ([Localization]
 * track_keep_share): does not build on main (63f48ba), which built the reference again
 * whenever the near keyframes changed at all. */
#include <gtest/gtest.h>
#include <lrgc/localization/Localizer.h>

using lrgc::CLocalizer;

TEST(LocalizerReference, keptWhileItHoldsTheNearestKeyframeAndTheShareOfTheNearOnes)
{
	const std::vector<size_t> current{10, 11, 12, 13, 14, 15, 16, 17};
	// Two keyframes ahead joined, two behind left: 6 of 8 held, the nearest among them.
	const std::vector<size_t> moved{12, 13, 14, 15, 16, 17, 18, 19};
	EXPECT_TRUE(CLocalizer::stillCovers(current, moved, 16, 0.5));
	EXPECT_TRUE(CLocalizer::stillCovers(current, moved, 16, 0.75));
	EXPECT_FALSE(CLocalizer::stillCovers(current, moved, 16, 0.8));
	// The nearest keyframe is new: built again whatever the share.
	EXPECT_FALSE(CLocalizer::stillCovers(current, moved, 18, 0.0));
	// 4 of 8 near ones held is enough at 0.5, 3 of 8 is not.
	const std::vector<size_t> far{14, 15, 16, 17, 18, 19, 20, 21};
	EXPECT_TRUE(CLocalizer::stillCovers(current, far, 15, 0.5));
	const std::vector<size_t> farther{15, 16, 17, 18, 19, 20, 21, 22};
	EXPECT_FALSE(CLocalizer::stillCovers(current, farther, 15, 0.5));
}

TEST(LocalizerReference, shareOneKeepsOnlyAReferenceHoldingEveryNearKeyframe)
{
	const std::vector<size_t> current{3, 4, 5, 6};
	EXPECT_TRUE(CLocalizer::stillCovers(current, {4, 5, 6}, 5, 1.0));
	EXPECT_FALSE(CLocalizer::stillCovers(current, {4, 5, 6, 7}, 5, 1.0));
	// No reference yet: always built.
	EXPECT_FALSE(CLocalizer::stillCovers({}, {4, 5}, 4, 0.0));
}
