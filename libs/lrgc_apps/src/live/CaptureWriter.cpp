#include "live/CaptureWriter.h"

#include <mrpt/core/exceptions.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace lrgc::apps
{
CCaptureWriter::CCaptureWriter(const std::string& path) : m_path(path)
{
	m_fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_APPEND | O_CLOEXEC, 0644);
	if (m_fd < 0)
		THROW_EXCEPTION_FMT("cannot create the capture file '%s': %s", path.c_str(),
							std::strerror(errno));
}

CCaptureWriter::~CCaptureWriter()
{
	try
	{
		close();
	}
	catch (...)
	{
		// A destructor cannot report; close() is called explicitly on the normal path.
	}
}

void CCaptureWriter::append(const mrpt::serialization::CSerializable& object)
{
	if (m_fd < 0) THROW_EXCEPTION_FMT("capture file '%s' is closed", m_path.c_str());
	mrpt::io::CMemoryStream buf;
	auto arch = mrpt::serialization::archiveFrom(buf);
	arch << object;
	const auto* data = static_cast<const char*>(buf.getRawBufferData());
	size_t left = static_cast<size_t>(buf.getTotalBytesCount());
	while (left > 0)
	{
		const ssize_t n = ::write(m_fd, data, left);
		if (n < 0 && errno == EINTR) continue;
		if (n <= 0)
			THROW_EXCEPTION_FMT(
				"cannot write to the capture file '%s' after %llu objects: %s", m_path.c_str(),
				static_cast<unsigned long long>(m_objects.load()), std::strerror(errno));
		data += n;
		left -= static_cast<size_t>(n);
		m_bytes += static_cast<uint64_t>(n);
	}
	++m_objects;
}

void CCaptureWriter::sync()
{
	std::lock_guard<std::mutex> lock(m_fdMutex);
	if (m_fd >= 0) (void)::fdatasync(m_fd);
}

void CCaptureWriter::close()
{
	std::lock_guard<std::mutex> lock(m_fdMutex);
	if (m_fd < 0) return;
	(void)::fdatasync(m_fd);
	const int fd = m_fd;
	m_fd = -1;
	if (::close(fd) != 0)
		THROW_EXCEPTION_FMT("error closing the capture file '%s': %s", m_path.c_str(),
							std::strerror(errno));
}

}  // namespace lrgc::apps
