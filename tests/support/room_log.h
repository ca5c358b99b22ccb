/* A small CARMEN log the tests make themselves: a robot driving down the middle of a
 * 12 x 6 m room (81 FLASER scans of 181 rays over 180 degrees, with odometry), mapped by
 * lrgc-slam in well under a second. */
#pragma once

#include <string>

namespace lrgc::test
{
/** The log's text (FLASER and ODOM lines, x from 2 to 10 m at y = 3 m, 0.2 s apart). */
std::string roomLog();

}  // namespace lrgc::test
