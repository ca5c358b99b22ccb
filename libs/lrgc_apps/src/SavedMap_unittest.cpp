/* loadSavedMap on a corrupted map.simplemap.gz (issue 30): a scan whose range count says
 * 300 million made MRPT allocate and zero-fill 1.5 GB in this process before the read failed
 * (13 GB in the case). Saved maps are now read as rawlogs are, through the guard's
 * child under its memory budget: the error names the file, and this process's peak resident
 * set grows by far less than the claimed size. A valid map still loads. */
#include <gtest/gtest.h>
#include <lrgc_apps/SavedMap.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/serialization/CArchive.h>

#include <unistd.h>

#include <cstring>
#include <fstream>

#include "io_test_files.h"
#include "test_data.h"

namespace
{
// The serialized bytes of a CSimpleMap of three keyframes of 181 readings of 3 m each.
std::string simplemapBytes()
{
	mrpt::maps::CSimpleMap map;
	for (int k = 0; k < 3; ++k)
	{
		auto scan = mrpt::obs::CObservation2DRangeScan::Create();
		scan->aperture = static_cast<float>(M_PI);
		scan->resizeScan(181);
		for (size_t i = 0; i < 181; ++i)
			scan->setScanRange(i, 3.0f), scan->setScanRangeValidity(i, true);
		auto sf = mrpt::obs::CSensoryFrame::Create();
		sf->insert(scan);
		auto pose = mrpt::poses::CPose3DPDFGaussian::Create();
		pose->mean = mrpt::poses::CPose3D(k, 0, 0, 0, 0, 0);
		map.insert(pose, sf);
	}
	mrpt::io::CMemoryStream mem;
	auto arch = mrpt::serialization::archiveFrom(mem);
	arch << map;
	return std::string(static_cast<const char*>(mem.getRawBufferData()),
					   mem.getTotalBytesCount());
}

// Peak resident set of this process [MiB] (VmHWM).
double peakRssMiB()
{
	std::ifstream f("/proc/self/status");
	for (std::string line; std::getline(f, line);)
		if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
	return 0;
}
}  // namespace

TEST(SavedMap, ValidSimplemapLoads)
{
	const std::string file = lrgc::test::makeTempDir("saved_map_valid") + "/map.simplemap.gz";
	lrgc::test::writeGzFile(file, simplemapBytes());
	EXPECT_EQ(lrgc::apps::loadSavedMap(file, "--localize").keyframes.size(), 3u);
}

TEST(SavedMap, CorruptedSizeIsRefusedWithoutAllocatingIt)
{
	std::string bytes = simplemapBytes();
	// The first scan's range count: uint32 181 followed by the float 3.0.
	const float three = 3.0f;
	std::string pattern(4, '\0'), value(4, '\0');
	const uint32_t n = 181, huge = 300'000'000;
	std::memcpy(pattern.data(), &n, 4);
	std::string withRange = pattern + std::string(reinterpret_cast<const char*>(&three), 4);
	const size_t at = bytes.find(withRange);
	ASSERT_NE(at, std::string::npos);
	std::memcpy(value.data(), &huge, 4);
	bytes.replace(at, 4, value);
	const std::string file = lrgc::test::makeTempDir("saved_map_corrupt") + "/map.simplemap.gz";
	lrgc::test::writeGzFile(file, bytes);

	const double before = peakRssMiB();
	try
	{
		(void)lrgc::apps::loadSavedMap(file, "--localize");
		ADD_FAILURE() << "a corrupted map loaded";
	}
	catch (const std::runtime_error& e)
	{
		const std::string what = e.what();
		EXPECT_NE(what.find("--localize '" + file + "': not a readable MRPT CSimpleMap"),
				  std::string::npos)
			<< what;
		EXPECT_EQ(what.find('\n'), std::string::npos) << what;
	}
	EXPECT_LT(peakRssMiB() - before, 300.0) << "the claimed 1.5 GB was allocated here";
}
