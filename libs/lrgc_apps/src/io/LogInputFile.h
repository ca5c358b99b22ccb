/* A log file opened for streaming, plain or gzip-compressed (told by its magic bytes).
 *
 * It counts the bytes of the uncompressed stream handed out (the places of error messages)
 * and, for gzip, checks at the end that the CRC-32 and the length of the data read match the
 * gzip trailer (RFC 1952, last 8 bytes of the file). zlib, behind MRPT's CFileGZInputStream,
 * returns a truncated gzip stream as a shorter one without complaint, so without this check
 * a log cut at an object or line boundary would pass for a complete one. Corrupt deflate data
 * (zlib reports -1, which CFileGZInputStream passes on as a huge size_t) throws.
 * Limitation: a multi-member gzip file (concatenated .gz) fails the trailer check.
 */
#pragma once

#include <mrpt/io/CFileGZInputStream.h>

#include <cstddef>
#include <cstdint>
#include <string>

namespace lrgc::apps
{
class CLogInputFile
{
public:
	/** Opens `path`; throws CLogReadError if it is missing or unreadable. */
	explicit CLogInputFile(const std::string& path);

	/** Up to `count` bytes; fewer only at the end of the data. Throws CLogReadError on
	 * corrupt compressed data. The signature lets mrpt::serialization::archiveFrom() use it. */
	size_t Read(void* buffer, size_t count);
	/** Not a writable stream: throws. */
	size_t Write(const void* buffer, size_t count);
	std::string getStreamDescription() const;

	const std::string& path() const { return m_path; }
	bool isGzip() const { return m_isGzip; }
	/** Bytes of the (uncompressed) stream handed out so far. */
	uint64_t position() const { return m_position; }
	/** True once Read() threw for corrupt compressed data. */
	bool hadDataError() const { return m_dataError; }
	/** True once a Read returned fewer bytes than asked. */
	bool reachedEnd() const { return m_reachedEnd; }
	/** In [0, 1]: position over the uncompressed size (gzip trailer) or the file size. */
	double fractionRead() const;
	/** Reads to the end of the data, then for gzip compares CRC-32 and length with the
	 * trailer; throws CLogReadError naming the uncompressed byte where the data stop. */
	void verifyCompleteAtEnd();

private:
	std::string m_path;
	mrpt::io::CFileGZInputStream m_in;
	bool m_isGzip = false;
	uint64_t m_fileSize = 0;
	uint32_t m_trailerCrc = 0, m_trailerSize = 0;  // gzip ISIZE: length mod 2^32
	uint32_t m_crc = 0;                            // CRC-32 of the bytes handed out so far
	uint64_t m_position = 0;
	bool m_reachedEnd = false;
	bool m_dataError = false;
};

/** CRC-32 (IEEE 802.3, as gzip) of `data` continuing from `crc` (0 to start). */
uint32_t crc32Update(uint32_t crc, const void* data, size_t size);

}  // namespace lrgc::apps
