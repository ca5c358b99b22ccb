/* Reading what lrgc-slam writes the way MRPT's programs read it: one serialized object from a
 * gzip file (map.simplemap.gz, map.gridmap.gz). */
#pragma once

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <string>

namespace lrgc::test
{
/** Deserializes `obj` from the gzip file `path` (MRPT's archive format). */
template <class T>
void readArchiveGz(const std::string& path, T& obj)
{
	mrpt::io::CFileGZInputStream f(path);
	auto arch = mrpt::serialization::archiveFrom(f);
	arch >> obj;
}
}  // namespace lrgc::test
