/* CGlobalLocalizer on a map too wide for its correlation grid (issue 30): --localize and
 * --initial-map refused any map larger than about 820 x 820 m with CCorrelationGrid's
 * internal message; the message now says how wide the map is and what to change. */
#include <gtest/gtest.h>
#include <lrgc/localization/GlobalLocalizer.h>

using namespace lrgc;

TEST(GlobalLocalizer, AMapTooWideForTheGridIsAClearError)
{
	CPoseGraph graph;
	TKeyframes keyframes;
	for (const double x : {0.0, 1000.0})  // two keyframes 1 km apart, a wall ahead of each
	{
		graph.addNode(mrpt::math::TPose2D(x, x, 0));
		TKeyframe kf;
		for (int i = -20; i <= 20; ++i) kf.scan.points.emplace_back(2.0, 0.05 * i);
		keyframes.push_back(std::move(kf));
	}
	try
	{
		const CGlobalLocalizer finder(graph, keyframes, TPatchCorrelatorParams{});
		ADD_FAILURE() << "a 1 x 1 km map at 5 cm was accepted";
	}
	catch (const std::exception& e)
	{
		const std::string what = e.what();
		EXPECT_NE(what.find("the map's scans span 1000 x 1002 m: too large to search whole"),
				  std::string::npos)
			<< what;
		EXPECT_NE(what.find("a coarser resolution (--config)"), std::string::npos) << what;
	}
	TPatchCorrelatorParams coarse;
	coarse.resolution_m = 0.1;  // 1 km fits at 10 cm
	EXPECT_NO_THROW(CGlobalLocalizer(graph, keyframes, coarse));
}
