/* A keyframe: a node of the LRGC map graph with its scan (paper 2.4: "nodes are robot poses
 * with associated scans"). The node's pose lives in CPoseGraph; this holds the data. */
#pragma once

#include <lrgc/scan_matching/Scan.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <deque>
#include <vector>

namespace lrgc
{
struct TKeyframe
{
	TScan2D scan;  //!< valid points in the robot frame, for matching
	/** The sensory frame as it came (laser and any other observations), for CSimpleMap and
	 * for rendering grid maps with MRPT's own insertion. */
	mrpt::obs::CSensoryFrame::Ptr observations;
	mrpt::obs::CObservation2DRangeScan::Ptr laser;
	size_t scanIndex = 0;  //!< index of the scan in the run (0-based)
	/** The mapping session whose scan `laser` is: 0 for a map's own run and for the keyframes
	 * of a map it continues, 1 for the session that continues it (CMetricMapBuilderLRGC::
	 * startSessionAt, initialize from a saved map). The grid shows each cell as the newest
	 * session that saw it (CIncrementalGrid). */
	size_t session = 0;
};
/** A deque: appending keeps every earlier keyframe where it is, so the loop-closing worker
 * can read old scans (through TScanRefs) while the mapping thread appends new keyframes. */
using TKeyframes = std::deque<TKeyframe>;
/** The scans of nodes 0..n-1, by address (stable: see TKeyframes). */
using TScanRefs = std::vector<const TScan2D*>;

}  // namespace lrgc
