/* SENA seen in a mirror (e2e tests): every scan's readings in reverse order (y -> -y in the
 * laser's frame), no odometry. Corridors and rooms alike, but a building no part of SENA's map
 * looks like scan by scan; a patch of its corridors can still pass the correlation's filters
 * somewhere (SlamSavedMap.senaSeenInAMirrorFindsNoStartAndJoinsNot). Header only: it reads the
 * rawlog with lrgc_apps, which the e2e tests link and lrgc_test_support does not. */
#pragma once

#include <lrgc_apps/io/LogReader.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/serialization/CArchive.h>

#include <string>

#include "test_data.h"

namespace lrgc::test
{
/** Writes SENA's scans mirrored, as a rawlog of empty actions and sensory frames, to `path`. */
inline void writeMirroredSena(const std::string& path)
{
	const auto reader = lrgc::apps::openLog(senaRawlogPath());
	mrpt::io::CFileGZOutputStream file(path);
	auto out = mrpt::serialization::archiveFrom(file);
	while (auto e = reader->next())
	{
		auto frame = mrpt::obs::CSensoryFrame::Create();
		for (const auto& obs : *e->observations)
		{
			auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs);
			if (!scan) continue;
			auto mirrored = mrpt::obs::CObservation2DRangeScan::Create(*scan);
			const size_t n = scan->getScanSize();
			for (size_t i = 0; i < n; ++i)
			{
				mirrored->setScanRange(i, scan->getScanRange(n - 1 - i));
				mirrored->setScanRangeValidity(i, scan->getScanRangeValidity(n - 1 - i));
			}
			frame->insert(mirrored);
		}
		out << mrpt::obs::CActionCollection() << *frame;
	}
}

}  // namespace lrgc::test
