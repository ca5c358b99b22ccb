/* Where tests find data: the project's own generated fixtures, Debian's mrpt-common
 * datasets, and the shared benchmark logs (../shared/datasets beside the checkout, or
 * $LRGC_SHARED_DATASETS). Tests that need data that is absent skip, saying so. */
#pragma once

#include <gtest/gtest.h>

#include <optional>
#include <string>

namespace lrgc::test
{
/** The SENA one-loop rawlog from Debian's mrpt-common. */
std::string senaRawlogPath();
/** Path of a file under the shared benchmark datasets, e.g. "intel/intel.clf.gz". */
std::string sharedDatasetPath(const std::string& relative);
/** A fresh empty directory under the build tree for one test's outputs. */
std::string makeTempDir(const std::string& name);
bool fileExists(const std::string& path);

}  // namespace lrgc::test

/** Skips the current test, naming the missing file, if `path` does not exist. */
#define LRGC_SKIP_IF_MISSING(path)                                    \
	do                                                                \
	{                                                                 \
		if (!::lrgc::test::fileExists(path))                          \
			GTEST_SKIP() << "test data not present here: " << (path); \
	} while (0)
