/* Shared by the libFuzzer targets: the readers and the .ini loader take paths, so each input
 * is written to a scratch file of this process first. A broken invariant aborts (libFuzzer
 * reports it as a crash with the input that broke it). */
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace lrgc::fuzz
{
/** A file in $TMPDIR (or /tmp) that this process rewrites for every input. */
inline const std::string& scratchPath(const char* name)
{
	static const std::string dir = []
	{
		const char* t = std::getenv("TMPDIR");
		return std::string(t && *t ? t : "/tmp");
	}();
	static thread_local std::string path;
	path = dir + "/lrgc-fuzz-" + std::to_string(::getpid()) + "-" + name;
	return path;
}

inline const std::string& writeScratch(const char* name, const uint8_t* data, size_t size)
{
	const std::string& path = scratchPath(name);
	std::FILE* f = std::fopen(path.c_str(), "wb");
	if (!f || (size > 0 && std::fwrite(data, 1, size, f) != size) || std::fclose(f) != 0)
	{
		std::perror(path.c_str());
		std::abort();
	}
	return path;
}

#define LRGC_FUZZ_CHECK(cond, what)                                                     \
	do                                                                                  \
	{                                                                                   \
		if (!(cond))                                                                    \
		{                                                                               \
			std::fprintf(stderr, "lrgc fuzz invariant broken: %s (%s)\n", what, #cond); \
			std::abort();                                                               \
		}                                                                               \
	} while (0)

}  // namespace lrgc::fuzz
