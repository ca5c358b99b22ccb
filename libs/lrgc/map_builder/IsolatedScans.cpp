#include <lrgc/map_builder/IsolatedScans.h>

#include <lrgc/common/se2.h>

#include <algorithm>

namespace lrgc
{
using mrpt::math::TPose2D;

namespace
{
constexpr size_t kMaxRun = 3;         //!< [scans] longest run that can be isolated
constexpr double kBridgeGate = 0.05;  //!< [m] the odometry must bridge the run this well
constexpr double kOffGate = 0.15;     //!< [m] a scan of the run is off the chain by more
constexpr double kOffFactor = 4;      //!< ... and by more than this times the bridge's residual

/** The odometry chain from scan a over steps a+1..b: the pose of each scan a+1..b [map]. */
std::vector<TPose2D> odometryChain(const std::vector<TScanStep>& s, size_t a, size_t b)
{
	std::vector<TPose2D> chain;
	TPose2D p = s[a].pose;
	for (size_t k = a + 1; k <= b; ++k) chain.push_back(p = compose(p, s[k].odometryStep));
	return chain;
}

/** Whether steps a+1..b all have odometry. */
bool candidateRun(const std::vector<TScanStep>& s, size_t a, size_t b)
{
	for (size_t k = a + 1; k <= b; ++k)
		if (!s[k].fromOdometry) return false;
	return true;
}
}  // namespace

std::vector<std::pair<size_t, TPose2D>> settleIsolatedScans(const std::vector<TScanStep>& s)
{
	std::vector<std::pair<size_t, TPose2D>> settled;
	for (size_t a = 0; a + 2 < s.size(); ++a)
		for (size_t len = 1; len <= kMaxRun && a + len + 1 < s.size(); ++len)
		{
			const size_t b = a + len + 1;
			if (!candidateRun(s, a, b)) continue;
			const std::vector<TPose2D> chain = odometryChain(s, a, b);
			const TPose2D bridge = between(chain.back(), s[b].pose);  // residual at b
			const double bridgeXY = translationNorm(bridge);
			if (bridgeXY > kBridgeGate) continue;
			bool allOff = true;
			for (size_t k = a + 1; k < b && allOff; ++k)
			{
				const double off = translationNorm(between(chain[k - a - 1], s[k].pose));
				allOff = off > kOffGate && off > kOffFactor * bridgeXY;
			}
			if (!allOff) continue;
			for (size_t k = a + 1; k < b; ++k)
			{
				const double f = double(k - a) / double(b - a);
				const TPose2D share(f * bridge.x, f * bridge.y, f * bridge.phi);
				settled.emplace_back(k, compose(chain[k - a - 1], share));
			}
			a = b - 1;  // the next run starts at b
			break;
		}
	return settled;
}

}  // namespace lrgc
