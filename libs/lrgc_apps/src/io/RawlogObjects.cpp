#include "io/RawlogObjects.h"

#include "lrgc_apps/io/LogReader.h"

#include <mrpt/core/format.h>

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <new>

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define LRGC_SANITIZED_BUILD 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define LRGC_SANITIZED_BUILD 1
#endif
#ifdef LRGC_SANITIZED_BUILD
#include <sanitizer/allocator_interface.h>
#include <sanitizer/common_interface_defs.h>

#include <atomic>
#endif

namespace lrgc::apps
{
using Result = TObjectRead::Result;

// How long the reader waits for the child's report on one object [ms].
constexpr int kReportTimeoutMs = 30000;
// The child's memory on top of what it had at fork [bytes].
constexpr size_t kChildMemoryBudget = size_t(2) << 30;
// Exit status of a child that went over its budget (sanitizer builds, below).
constexpr int kChildOutOfMemoryExit = 3;
constexpr const char* kOutOfMemoryProblem =
	"corrupt object (a size field asks for more memory than exists)";

namespace
{
// MRPT exception texts nest "==== MRPT exception ==== Message: ... Location: ..." blocks
// with call stacks: keep the innermost message, printable and short.
std::string compactMessage(const std::string& what)
{
	std::string msg = what;
	const size_t m = what.rfind("Message:");
	if (m != std::string::npos)
	{
		const size_t from = m + 8;
		const size_t loc = what.find("Location:", from);
		msg = what.substr(from, loc == std::string::npos ? std::string::npos : loc - from);
	}
	std::string out;
	for (const char c : msg)
	{
		const auto u = static_cast<unsigned char>(c);
		const char k = (u < 32 || u > 126) ? ' ' : c;
		if (k == ' ' && (out.empty() || out.back() == ' ')) continue;
		out += k;
	}
	while (!out.empty() && out.back() == ' ') out.pop_back();
	if (out.size() > 200) out = out.substr(0, 200) + "...";
	return out;
}

TObjectRead failed(uint64_t at, std::string problem)
{
	TObjectRead r;
	r.result = Result::Failed;
	r.place = "byte " + std::to_string(at);
	r.problem = std::move(problem);
	return r;
}
}  // namespace

TObjectRead readArchiveObject(CLogInputFile& in, TArchive& archive)
{
	const uint64_t start = in.position();
	std::string what;
	bool outOfMemory = false;
	try
	{
		TObjectRead r;
		r.result = Result::Parsed;
		r.object = archive.ReadObject();
		return r;
	}
	catch (const std::bad_alloc&)
	{
		outOfMemory = true;
	}
	catch (const std::exception& e)
	{
		what = e.what();
	}
	catch (...)
	{
		what = "unknown exception";
	}
	if (in.hadDataError())
		return failed(in.position(), "corrupt gzip data (zlib cannot inflate past this point)");
	if (in.position() == start && in.reachedEnd()) return TObjectRead{};  // clean end
	if (outOfMemory) return failed(start, kOutOfMemoryProblem);
	if (in.reachedEnd())
		return failed(
			start,
			mrpt::format("truncated: the object starting here is cut short by the end of the "
						 "data at byte %llu",
						 static_cast<unsigned long long>(in.position())));
	return failed(start, "corrupt object: " + compactMessage(what));
}

// ------------------------------------------------------------------ the guard's child
namespace
{
bool writeAll(int fd, const void* data, size_t n)
{
	const auto* p = static_cast<const char*>(data);
	while (n > 0)
	{
		const ssize_t w = ::write(fd, p, n);
		if (w < 0 && errno == EINTR) continue;
		if (w <= 0) return false;
		p += w;
		n -= static_cast<size_t>(w);
	}
	return true;
}

bool readAll(int fd, void* data, size_t n)
{
	auto* p = static_cast<char*>(data);
	while (n > 0)
	{
		const ssize_t r = ::read(fd, p, n);
		if (r < 0 && errno == EINTR) continue;
		if (r <= 0) return false;
		p += r;
		n -= static_cast<size_t>(r);
	}
	return true;
}

bool writeString(int fd, const std::string& s)
{
	const auto n = static_cast<uint32_t>(s.size());
	return writeAll(fd, &n, sizeof(n)) && writeAll(fd, s.data(), n);
}

bool readString(int fd, std::string& s)
{
	uint32_t n = 0;
	if (!readAll(fd, &n, sizeof(n)) || n > (1u << 20)) return false;
	s.resize(n);
	return readAll(fd, s.data(), n);
}

// Address space now [bytes], from /proc/self/statm (first field: pages).
rlim_t currentAddressSpace()
{
	unsigned long long pages = 0;
	if (FILE* f = std::fopen("/proc/self/statm", "r"))
	{
		if (std::fscanf(f, "%llu", &pages) != 1) pages = 0;
		std::fclose(f);
	}
	return static_cast<rlim_t>(pages) * static_cast<rlim_t>(::sysconf(_SC_PAGESIZE));
}

#ifdef LRGC_SANITIZED_BUILD
// A sanitizer's allocator reserves its address space up front, so RLIMIT_AS does not bound
// the heap of a sanitized child (the fuzzers found a corrupt CActionCollection size taking
// 4 GiB through it): count its bytes instead. Set in the child only, after fork; bytes freed
// that were allocated before the fork make it negative, which is harmless. The budget is
// smaller than a normal build's: a sanitized build is the fuzzers', whose inputs are at most
// 16 KiB, and filling gigabytes under a sanitizer takes seconds per input.
constexpr long long kSanitizedChildHeapBudget = 64LL << 20;
std::atomic<long long> g_childHeapBytes{0};

void onChildMalloc(const volatile void*, size_t size)
{
	if (g_childHeapBytes.fetch_add(static_cast<long long>(size)) +
			static_cast<long long>(size) >
		kSanitizedChildHeapBudget)
		::_exit(kChildOutOfMemoryExit);
}

void onChildFree(const volatile void* p)
{
	if (p)
		g_childHeapBytes.fetch_sub(
			static_cast<long long>(__sanitizer_get_allocated_size(const_cast<void*>(p))));
}
#endif

// The child is the reader's disposable stand-in: it dies by a fault of MRPT's deserializer
// itself, whatever handler the host program installed (a crash reporter, a sanitizer), so
// that the reader can name the signal; it ignores the stop signals a terminal or a service
// manager sends to the whole process group (Ctrl-C, a closed terminal, `timeout`, systemd: the
// reader decides when to stop, and kills it; had the child died of it, the reader would have
// reported the object it was on as corrupt); it dies of SIGPIPE at its next report once the
// reader is gone (not PR_SET_PDEATHSIG, which fires when the thread that forked ends, not the
// process); and it speaks only through the pipe (MRPT's messages on an object are the reader's
// to print).
void becomeQuietDisposableChild()
{
	for (const int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGPIPE})
		::signal(sig, SIG_DFL);
	::signal(SIGINT, SIG_IGN);
	::signal(SIGTERM, SIG_IGN);
	::signal(SIGHUP, SIG_IGN);
	const int devNull = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
	if (devNull >= 0)
	{
		::dup2(devNull, STDOUT_FILENO);
		::dup2(devNull, STDERR_FILENO);
		::close(devNull);
	}
#ifdef LRGC_SANITIZED_BUILD
	// A sanitizer's report of an allocation MRPT asks for from a corrupt size field (here a
	// std::bad_alloc in a normal build) ends the child like a crash does; the death callback
	// belongs to the parent (libFuzzer records the parent's input as a crash there).
	__sanitizer_set_death_callback(nullptr);
	__sanitizer_install_malloc_and_free_hooks(onChildMalloc, onChildFree);
#endif
}

// Never returns and never flushes the parent's stdio buffers (_exit).
[[noreturn]] void runChild(const std::string& path, int fd)
{
	becomeQuietDisposableChild();
	if (FILE* f = std::fopen("/proc/self/oom_score_adj", "w"))
	{
		std::fputs("1000", f);
		std::fclose(f);
	}
	const rlim_t limit = currentAddressSpace() + rlim_t(kChildMemoryBudget);
	const rlimit rl{limit, limit};
	::setrlimit(RLIMIT_AS, &rl);
	try
	{
		CLogInputFile in(path);
		TArchive archive(in);
		while (true)
		{
			const TObjectRead r = readArchiveObject(in, archive);
			const char code = static_cast<char>(r.result);
			if (!writeAll(fd, &code, 1)) break;
			if (r.result == Result::Parsed) continue;
			if (r.result == Result::Failed)
				writeString(fd, r.place), writeString(fd, r.problem);
			break;
		}
	}
	catch (...)
	{
	}
	::_exit(0);
}
}  // namespace

CDeserializationGuard::CDeserializationGuard(const std::string& path)
{
	int fds[2];
	if (::pipe2(fds, O_CLOEXEC) != 0) return;
	const pid_t pid = ::fork();
	if (pid < 0)
	{
		::close(fds[0]);
		::close(fds[1]);
		return;
	}
	if (pid == 0)
	{
		::close(fds[0]);
		runChild(path, fds[1]);
	}
	::close(fds[1]);
	m_pid = pid;
	m_fd = fds[0];
}

CDeserializationGuard::~CDeserializationGuard()
{
	if (m_fd >= 0) ::close(m_fd);
	if (m_pid > 0)
	{
		::kill(m_pid, SIGKILL);
		int status = 0;
		while (::waitpid(m_pid, &status, 0) < 0 && errno == EINTR)
		{
		}
	}
}

TObjectRead CDeserializationGuard::checkNextObject(uint64_t objectStart)
{
	TObjectRead r;
	r.result = Result::Parsed;
	if (!active() || m_childDone) return r;
	// A child stuck (a lock held by another thread at fork time, an endless loop in MRPT):
	// give up guarding rather than hang the run.
	pollfd pfd{m_fd, POLLIN, 0};
	int ready;
	do ready = ::poll(&pfd, 1, kReportTimeoutMs);
	while (ready < 0 && errno == EINTR);
	if (ready == 0)
	{
		::kill(m_pid, SIGKILL);
		int status = 0;
		while (::waitpid(m_pid, &status, 0) < 0 && errno == EINTR)
		{
		}
		m_pid = -1;
		m_gaveUp = true;
		return r;
	}
	char code = 0;
	if (readAll(m_fd, &code, 1))
	{
		r.result = static_cast<Result>(code);
		if (r.result == Result::Parsed) return r;
		m_childDone = true;
		if (r.result == Result::Failed &&
			!(readString(m_fd, r.place) && readString(m_fd, r.problem)))
			r.problem = "corrupt object (the guard's report was cut short)";
		return r;
	}
	// No report: the child died on this object. Reap it and say how.
	int status = 0;
	pid_t w;
	do w = ::waitpid(m_pid, &status, 0);
	while (w < 0 && errno == EINTR);
	m_pid = -1;
	if (w > 0 && WIFEXITED(status) && WEXITSTATUS(status) == kChildOutOfMemoryExit)
		return failed(objectStart, kOutOfMemoryProblem);
	std::string how = "it vanished";
	if (w > 0 && WIFSIGNALED(status))
		how =
			"signal " + std::to_string(WTERMSIG(status)) + ", " + ::strsignal(WTERMSIG(status));
	else if (w > 0 && WIFEXITED(status))
		how = "exit status " + std::to_string(WEXITSTATUS(status));
	r.result = Result::Failed;
	r.place = "byte " + std::to_string(objectStart);
	r.problem =
		"corrupt object: MRPT's deserializer crashed on it in the guard process (" + how + ")";
	return r;
}

}  // namespace lrgc::apps
