#include "atomic_file.h"

#include <mrpt/core/exceptions.h>

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace lrgc::apps
{
namespace
{
void fsyncPath(const std::string& path)
{
	const int fd = ::open(path.c_str(), O_RDONLY);
	if (fd < 0) return;
	(void)::fsync(fd);
	::close(fd);
}
}  // namespace

void writeFileAtomically(
	const std::string& path, const std::function<void(const std::string& tmpPath)>& writer)
{
	namespace fs = std::filesystem;
	const fs::path dest(path);
	// Temporary name in the same directory (same file system), unique per process; it keeps
	// the destination's extension so writers that look at it (e.g. ".gz") behave the same.
	const fs::path tmp = dest.parent_path() /
		(".tmp." + std::to_string(::getpid()) + "." + dest.filename().string());
	try
	{
		writer(tmp.string());
		if (!fs::exists(tmp))
			THROW_EXCEPTION_FMT("writer did not create '%s'", tmp.string().c_str());
		fsyncPath(tmp.string());
		if (std::rename(tmp.c_str(), dest.c_str()) != 0)
			THROW_EXCEPTION_FMT(
				"cannot rename '%s' to '%s': %s", tmp.string().c_str(), path.c_str(),
				std::strerror(errno));
		fsyncPath(dest.parent_path().empty() ? "." : dest.parent_path().string());
	}
	catch (...)
	{
		std::error_code ec;
		fs::remove(tmp, ec);
		throw;
	}
}

void writeTextFileAtomically(const std::string& path, const std::string& contents)
{
	writeFileAtomically(path, [&](const std::string& tmp) {
		std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
		if (!f)
			THROW_EXCEPTION_FMT("cannot create '%s' (%s)", tmp.c_str(), std::strerror(errno));
		f << contents;
		f.close();
		if (!f) THROW_EXCEPTION_FMT("error writing '%s' (disk full?)", tmp.c_str());
	});
}

}  // namespace lrgc::apps
