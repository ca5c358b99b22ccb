/* TScanMatcherParams ([ScanMatcher]): a text round trip, unknown keys and invalid values. */
#include <gtest/gtest.h>
#include <lrgc/scan_matching/ScanMatcher.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>

using namespace lrgc;

TEST(ScanMatcherParams, roundTripUnknownKeysAndValidation)
{
	TScanMatcherParams p;
	p.max_iterations = 33;
	p.normal_radius_m = 0.21;
	p.wide_search_step = 5 * M_PI / 180;
	mrpt::config::CConfigFileMemory saved;
	p.saveToConfigFile(saved, "ScanMatcher");
	std::string text;
	saved.getContent(text);  // as in a file: a text round trip
	const mrpt::config::CConfigFileMemory mem(text);
	TScanMatcherParams q;
	q.loadFromConfigFile(mem, "ScanMatcher");
	EXPECT_EQ(q.max_iterations, 33);
	EXPECT_DOUBLE_EQ(q.normal_radius_m, 0.21);
	EXPECT_NEAR(q.wide_search_step, 5 * M_PI / 180, 1e-12);
	EXPECT_NEAR(mem.read_double("ScanMatcher", "wide_search_step_deg", 0), 5.0, 1e-12);

	mrpt::config::CConfigFileMemory bad;
	bad.write("ScanMatcher", "normalRadius", 0.2);  // misspelt key
	EXPECT_THROW(q.loadFromConfigFile(bad, "ScanMatcher"), std::exception);
	mrpt::config::CConfigFileMemory invalid;
	invalid.write("ScanMatcher", "min_inlier_fraction", 1.5);
	EXPECT_THROW(q.loadFromConfigFile(invalid, "ScanMatcher"), std::exception);
	EXPECT_EQ(q.max_iterations, 33);  // a failed load leaves the values untouched
	TScanMatcherParams neg;
	neg.max_correspondence_dist_m = -1;
	EXPECT_THROW(CScanMatcher{neg}, std::exception);
}
