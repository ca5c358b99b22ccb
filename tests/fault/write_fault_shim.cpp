/* An LD_PRELOAD library that makes a full disk appear on demand, for the disk-full sweep of
 * tests/slam_disk_full_test.cpp. It needs no root and no special file system.
 *
 * Only writes to files under $LRGC_FAULT_DIR count (the fd's /proc/self/fd link is compared
 * with that prefix; the terminal, pipes and other files pass through untouched). After
 * $LRGC_FAULT_WRITE_AFTER bytes have been written there, the write that crosses the limit is
 * cut short at it and every later one fails with ENOSPC, as write(2) on a full file system
 * does. With $LRGC_FAULT_FSYNC=EIO, fsync(2) of such a file fails with EIO instead (the
 * report of a lost write-back). write, pwrite, pwrite64 and writev are wrapped. */
#include <dlfcn.h>
#include <sys/uio.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <mutex>

namespace
{
std::mutex g_mutex;
long long g_left = -2;  // bytes still allowed; -2: not read yet, -1: no limit

bool underFaultDir(int fd)
{
	const char* dir = std::getenv("LRGC_FAULT_DIR");
	if (!dir || !*dir) return false;
	char link[64], target[PATH_MAX];
	std::snprintf(link, sizeof(link), "/proc/self/fd/%d", fd);
	const ssize_t n = ::readlink(link, target, sizeof(target) - 1);
	if (n <= 0) return false;
	target[n] = '\0';
	return std::strncmp(target, dir, std::strlen(dir)) == 0;
}

// How many of `count` bytes this write may put down: count, fewer, or -1 (ENOSPC).
ssize_t allowed(int fd, size_t count)
{
	if (!underFaultDir(fd)) return static_cast<ssize_t>(count);
	std::lock_guard<std::mutex> lock(g_mutex);
	if (g_left == -2)
	{
		const char* v = std::getenv("LRGC_FAULT_WRITE_AFTER");
		g_left = v ? std::atoll(v) : -1;
	}
	if (g_left < 0 || static_cast<long long>(count) <= g_left)
	{
		if (g_left >= 0) g_left -= static_cast<long long>(count);
		return static_cast<ssize_t>(count);
	}
	if (g_left == 0) return -1;
	const ssize_t part = static_cast<ssize_t>(g_left);
	g_left = 0;
	return part;
}

template <class F>
F real(const char* name)
{
	return reinterpret_cast<F>(::dlsym(RTLD_NEXT, name));
}
}  // namespace

extern "C" ssize_t write(int fd, const void* buf, size_t count)
{
	static const auto next = real<ssize_t (*)(int, const void*, size_t)>("write");
	const ssize_t n = allowed(fd, count);
	if (n < 0) return errno = ENOSPC, -1;
	return next(fd, buf, static_cast<size_t>(n));
}

extern "C" ssize_t pwrite(int fd, const void* buf, size_t count, off_t offset)
{
	static const auto next = real<ssize_t (*)(int, const void*, size_t, off_t)>("pwrite");
	const ssize_t n = allowed(fd, count);
	if (n < 0) return errno = ENOSPC, -1;
	return next(fd, buf, static_cast<size_t>(n), offset);
}

extern "C" ssize_t pwrite64(int fd, const void* buf, size_t count, off64_t offset)
{
	static const auto next = real<ssize_t (*)(int, const void*, size_t, off64_t)>("pwrite64");
	const ssize_t n = allowed(fd, count);
	if (n < 0) return errno = ENOSPC, -1;
	return next(fd, buf, static_cast<size_t>(n), offset);
}

extern "C" ssize_t writev(int fd, const struct iovec* iov, int iovcnt)
{
	static const auto next = real<ssize_t (*)(int, const struct iovec*, int)>("writev");
	size_t total = 0;
	for (int i = 0; i < iovcnt; ++i) total += iov[i].iov_len;
	const ssize_t n = allowed(fd, total);
	if (n < 0) return errno = ENOSPC, -1;
	if (static_cast<size_t>(n) == total) return next(fd, iov, iovcnt);
	// Cut short: write the first n bytes only (through write, already accounted for).
	static const auto nextWrite = real<ssize_t (*)(int, const void*, size_t)>("write");
	size_t left = static_cast<size_t>(n), done = 0;
	for (int i = 0; i < iovcnt && left > 0; ++i)
	{
		const size_t k = iov[i].iov_len < left ? iov[i].iov_len : left;
		const ssize_t w = nextWrite(fd, iov[i].iov_base, k);
		if (w < 0) return done ? static_cast<ssize_t>(done) : -1;
		done += static_cast<size_t>(w);
		left -= k;
	}
	return static_cast<ssize_t>(done);
}

extern "C" int fsync(int fd)
{
	static const auto next = real<int (*)(int)>("fsync");
	const char* mode = std::getenv("LRGC_FAULT_FSYNC");
	if (mode && std::strcmp(mode, "EIO") == 0 && underFaultDir(fd)) return errno = EIO, -1;
	return next(fd);
}
