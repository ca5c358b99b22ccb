#include "room_log.h"

#include <mrpt/math/TPose2D.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "io_test_files.h"

namespace lrgc::test
{
namespace
{
// Range [m] from (x, y) along `angle` [rad] to the walls of the room [0, 12] x [0, 6].
double rangeInRoom(double x, double y, double angle)
{
	const double c = std::cos(angle), s = std::sin(angle);
	double r = 1e9;
	if (c > 1e-9) r = std::min(r, (12.0 - x) / c);
	if (c < -1e-9) r = std::min(r, -x / c);
	if (s > 1e-9) r = std::min(r, (6.0 - y) / s);
	if (s < -1e-9) r = std::min(r, -y / s);
	return r;
}
}  // namespace

std::string roomLog()
{
	std::string log;
	for (int k = 0; k <= 80; ++k)
	{
		const mrpt::math::TPose2D robot(2.0 + 0.1 * k, 3.0, 0.0);
		std::vector<double> ranges;
		for (int i = 0; i <= 180; ++i)
			ranges.push_back(rangeInRoom(robot.x, robot.y, (i - 90) * M_PI / 180.0));
		const double t = 1000.0 + 0.2 * k;
		log += odomLine(robot, t);
		log += flaserLine(ranges, robot, robot, t + 0.01);
	}
	return log;
}

}  // namespace lrgc::test
