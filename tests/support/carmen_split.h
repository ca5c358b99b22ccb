/* Splits a CARMEN log (.clf, plain or gzip) in two halves by file lines, for tests that map
 * the first half and continue or localise with the second: header lines ('#' comments and
 * PARAM lines) go into both halves, the other lines (ODOM, FLASER, ...) are divided at the
 * middle, in file order. */
#pragma once

#include <cstddef>
#include <string>

namespace lrgc::test
{
struct TSplitCounts
{
	size_t headerLines = 0, firstDataLines = 0, secondDataLines = 0;
};

/** Writes the halves of `log` to `firstOut` and `secondOut` (plain text). Throws if `log`
 * cannot be read or holds no data line. */
TSplitCounts splitCarmenLog(const std::string& log, const std::string& firstOut,
							const std::string& secondOut);

}  // namespace lrgc::test
