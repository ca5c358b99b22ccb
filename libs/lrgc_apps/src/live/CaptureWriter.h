/* CCaptureWriter: DIR/capture.rawlog of a live run, written as the data arrives.
 *
 * The file is an MRPT rawlog in the observations-only layout (layout 2; a flat sequence of
 * serialized objects, the layout rawlog-grabber writes without sensory frames), uncompressed so
 * that every object is on disk as soon as it is appended: a gzip stream would hold data back
 * and be unreadable after an abrupt exit. Each object is serialized in memory first and then
 * written with one write(2) on an O_APPEND descriptor, so whatever ends the process (a second
 * Ctrl-C, which calls _exit, or a crash) the file is a sequence of whole objects, readable by
 * `lrgc-slam --input`, rawlog-edit or RawLogViewer. sync() (fdatasync) is called at every
 * periodic save and at the end, so a power loss loses at most what came since the last save.
 * An existing file is never overwritten.
 */
#pragma once

#include <mrpt/serialization/CSerializable.h>

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>

namespace lrgc::apps
{
class CCaptureWriter
{
public:
	/** Creates `path`; throws (naming it) if it exists or cannot be created. */
	explicit CCaptureWriter(const std::string& path);
	~CCaptureWriter();
	CCaptureWriter(const CCaptureWriter&) = delete;
	CCaptureWriter& operator=(const CCaptureWriter&) = delete;

	/** Appends one object; throws on a write error (disk full, ...). One thread at a time. */
	void append(const mrpt::serialization::CSerializable& object);
	/** Flushes the file's data to the device (fdatasync); callable from any thread. */
	void sync();
	/** sync() and close; later appends throw. Idempotent. */
	void close();

	const std::string& path() const { return m_path; }
	uint64_t objects() const { return m_objects; }
	uint64_t bytes() const { return m_bytes; }

private:
	std::string m_path;
	std::mutex m_fdMutex;  //!< sync() from other threads vs close()
	int m_fd = -1;
	std::atomic<uint64_t> m_objects{0}, m_bytes{0};
};

}  // namespace lrgc::apps
