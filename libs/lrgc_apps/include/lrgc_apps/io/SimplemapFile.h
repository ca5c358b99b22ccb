/* Reading a saved map's CSimpleMap file (map.simplemap.gz, icp-slam's .simplemap) as rawlogs
 * are read (RawlogObjects.h): the deserialization guard's child meets the object first, under
 * the memory budget, so a corrupted size cannot make this process allocate without bound
 * (13 GB before bad_alloc, issue 30) nor crash it in MRPT's deserializer. */
#pragma once

#include <mrpt/maps/CSimpleMap.h>

#include <string>

namespace lrgc::apps
{
/** The CSimpleMap in `file` (plain or gzip), at least one keyframe. Throws std::runtime_error,
 * one line naming `option`, the file and the problem. */
mrpt::maps::CSimpleMap readSimplemapFile(const std::string& file, const std::string& option);

}  // namespace lrgc::apps
