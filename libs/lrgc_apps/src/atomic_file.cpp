#include "atomic_file.h"

#include <mrpt/core/exceptions.h>
#include <mrpt/io/CStream.h>
#include <mrpt/serialization/CArchive.h>

#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <vector>

namespace lrgc::apps
{
namespace
{
namespace fs = std::filesystem;

// Temporary name in the destination's directory (same file system, so rename(2) is atomic),
// unique per process; it keeps the destination's name at its end so that writers which look
// at the extension (e.g. ".gz") behave the same.
fs::path temporaryFor(const fs::path& dest)
{
	return dest.parent_path() /
		   (".tmp." + std::to_string(::getpid()) + "." + dest.filename().string());
}

[[noreturn]] void throwWriteError(const std::string& shownPath, const char* step, int err)
{
	THROW_EXCEPTION_FMT("cannot write '%s' (%s): %s", shownPath.c_str(), step,
						std::strerror(err));
}

// fsync(2) of a file or a directory; a file's failure is an error (its data may not be on
// disk), a directory's is not (some file systems refuse to fsync directories).
void fsyncPath(const std::string& path, const std::string& shownPath, bool mustSucceed)
{
	const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
	if (fd < 0)
	{
		if (mustSucceed) throwWriteError(shownPath, "open for fsync", errno);
		return;
	}
	const bool ok = ::fsync(fd) == 0;
	const int err = errno;
	const bool closed = ::close(fd) == 0;
	if (mustSucceed && !ok) throwWriteError(shownPath, "fsync", err);
	if (mustSucceed && !closed) throwWriteError(shownPath, "close", errno);
}

// Renames the complete temporary over the destination, then syncs the directory entry.
void publish(const fs::path& tmp, const fs::path& dest)
{
	if (std::rename(tmp.c_str(), dest.c_str()) != 0)
		THROW_EXCEPTION_FMT("cannot rename '%s' to '%s': %s", tmp.string().c_str(),
							dest.string().c_str(), std::strerror(errno));
	fsyncPath(dest.parent_path().empty() ? "." : dest.parent_path().string(), dest.string(),
			  false);
}

/* An output file written only through write(2), every call checked (EINTR and short writes
 * retried), optionally gzip-deflated on the way (zlib's deflate into our own buffer, so no
 * library write escapes the checks). finish() writes the rest, fsyncs and closes, each
 * checked. Errors name `shownPath`, the destination the user asked for. */
class CCheckedFile final : public mrpt::io::CStream
{
public:
	CCheckedFile(const std::string& path, std::string shownPath, TFileCompression compression)
		: m_shown(std::move(shownPath)), m_gzip(compression == TFileCompression::Gzip)
	{
		m_fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
		if (m_fd < 0) throwWriteError(m_shown, "create", errno);
		m_buffer.resize(kBufferBytes);
		// windowBits 15 + 16: a gzip header and trailer around the deflate stream; level 1 and
		// memLevel 8 as gzopen(path, "wb1") (what CFileGZOutputStream does).
		if (m_gzip &&
			::deflateInit2(&m_z, 1, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
			THROW_EXCEPTION_FMT("cannot write '%s': zlib deflateInit2 failed", m_shown.c_str());
	}
	~CCheckedFile() override
	{
		if (m_gzip) ::deflateEnd(&m_z);
		if (m_fd >= 0) ::close(m_fd);  // only after a failure: finish() closed it otherwise
	}
	CCheckedFile(const CCheckedFile&) = delete;
	CCheckedFile& operator=(const CCheckedFile&) = delete;

	size_t Read(void*, size_t) override { THROW_EXCEPTION("CCheckedFile is an output stream"); }
	size_t Write(const void* data, size_t count) override
	{
		if (m_gzip)
			deflateSome(data, count, Z_NO_FLUSH);
		else
			append(static_cast<const char*>(data), count);
		m_position += count;
		return count;
	}
	uint64_t Seek(int64_t, mrpt::io::CStream::TSeekOrigin) override
	{
		THROW_EXCEPTION("CCheckedFile cannot seek");
	}
	uint64_t getTotalBytesCount() const override { return m_position; }
	uint64_t getPosition() const override { return m_position; }

	/** Writes what is buffered (and the gzip trailer), then fsync and close, all checked. */
	void finish()
	{
		if (m_gzip) deflateSome(nullptr, 0, Z_FINISH);
		flushBuffer();
		if (::fsync(m_fd) != 0) throwWriteError(m_shown, "fsync", errno);
		const int fd = m_fd;
		m_fd = -1;
		if (::close(fd) != 0) throwWriteError(m_shown, "close", errno);
	}

private:
	static constexpr size_t kBufferBytes = 1 << 16;

	void append(const char* data, size_t count)
	{
		while (count > 0)
		{
			const size_t n = std::min(count, m_buffer.size() - m_used);
			std::memcpy(m_buffer.data() + m_used, data, n);
			m_used += n;
			data += n;
			count -= n;
			if (m_used == m_buffer.size()) flushBuffer();
		}
	}

	// Deflates `count` bytes into the buffer, writing it out whenever it fills; with
	// Z_FINISH, until zlib reports the stream's end (trailer included).
	void deflateSome(const void* data, size_t count, int flush)
	{
		m_z.next_in = static_cast<Bytef*>(const_cast<void*>(data));
		m_z.avail_in = static_cast<uInt>(count);  // archives write far less than 4 GiB at once
		for (;;)
		{
			m_z.next_out = reinterpret_cast<Bytef*>(m_buffer.data() + m_used);
			m_z.avail_out = static_cast<uInt>(m_buffer.size() - m_used);
			const int r = ::deflate(&m_z, flush);
			if (r == Z_STREAM_ERROR)
				THROW_EXCEPTION_FMT("cannot write '%s': zlib deflate failed", m_shown.c_str());
			m_used = m_buffer.size() - m_z.avail_out;
			if (m_used == m_buffer.size()) flushBuffer();
			if (flush == Z_FINISH ? r == Z_STREAM_END
								  : (m_z.avail_in == 0 && m_z.avail_out > 0))
				return;
		}
	}

	void flushBuffer()
	{
		const char* p = m_buffer.data();
		size_t left = m_used;
		while (left > 0)
		{
			const ssize_t n = ::write(m_fd, p, left);
			if (n < 0 && errno == EINTR) continue;
			if (n < 0) throwWriteError(m_shown, "write", errno);
			if (n == 0) throwWriteError(m_shown, "write", ENOSPC);
			p += n;
			left -= static_cast<size_t>(n);
		}
		m_used = 0;
	}

	std::string m_shown;
	bool m_gzip;
	int m_fd = -1;
	z_stream m_z{};
	std::vector<char> m_buffer;
	size_t m_used = 0;
	uint64_t m_position = 0;
};
}  // namespace

void writeFileAtomically(const std::string& path,
						 const std::function<void(const std::string& tmpPath)>& writer)
{
	const fs::path dest(path);
	const fs::path tmp = temporaryFor(dest);
	try
	{
		writer(tmp.string());
		if (!fs::exists(tmp))
			THROW_EXCEPTION_FMT("writer did not create '%s'", tmp.string().c_str());
		fsyncPath(tmp.string(), path, true);
		publish(tmp, dest);
	}
	catch (...)
	{
		std::error_code ec;
		fs::remove(tmp, ec);
		throw;
	}
}

void writeArchiveAtomically(const std::string& path, TFileCompression compression,
							const std::function<void(mrpt::serialization::CArchive&)>& writer)
{
	const fs::path dest(path);
	const fs::path tmp = temporaryFor(dest);
	try
	{
		{
			CCheckedFile file(tmp.string(), path, compression);
			auto archive = mrpt::serialization::archiveFrom(file);
			writer(archive);
			file.finish();
		}
		publish(tmp, dest);
	}
	catch (...)
	{
		std::error_code ec;
		fs::remove(tmp, ec);
		throw;
	}
}

void writeTextFileAtomically(const std::string& path, std::string_view contents)
{
	writeArchiveAtomically(path, TFileCompression::None,
						   [&](mrpt::serialization::CArchive& a)
						   { a.WriteBuffer(contents.data(), contents.size()); });
}

}  // namespace lrgc::apps
