#include "io/LogInputFile.h"

#include "lrgc_apps/io/LogReader.h"

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <vector>

#include <zlib.h>

namespace lrgc::apps
{
namespace
{
// Byte-wise CRC-32 table, reflected polynomial 0xEDB88320 (RFC 1952, section 8).
constexpr std::array<uint32_t, 256> makeCrcTable()
{
	std::array<uint32_t, 256> table{};
	for (uint32_t n = 0; n < 256; ++n)
	{
		uint32_t c = n;
		for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
		table[n] = c;
	}
	return table;
}
constexpr std::array<uint32_t, 256> kCrcTable = makeCrcTable();

uint32_t littleEndian32(const unsigned char* b)
{
	return uint32_t(b[0]) | uint32_t(b[1]) << 8 | uint32_t(b[2]) << 16 | uint32_t(b[3]) << 24;
}

/* The uncompressed length of a whole gzip file, inflated member by member: RFC 1952 lets
 * members follow one another (`cat a.gz b.gz`), and zero bytes after the last one are padding
 * (tape blocks; gzip(1) accepts them too). zlib checks each member's CRC-32 and length.
 * nullopt if a member is cut short or corrupt, or anything but zeros follows a member that
 * is not the start of another. */
std::optional<uint64_t> inflatedLengthOfMembers(const std::string& path)
{
	std::ifstream f(path, std::ios::binary);
	z_stream z{};
	if (!f || ::inflateInit2(&z, 15 + 16) != Z_OK) return std::nullopt;
	std::vector<unsigned char> in(1 << 16), out(1 << 16);
	uint64_t total = 0;
	bool inMember = true, padding = false, ok = true;
	while (ok)
	{
		if (z.avail_in == 0)
		{
			f.read(reinterpret_cast<char*>(in.data()), static_cast<std::streamsize>(in.size()));
			if (f.gcount() <= 0) break;
			z.next_in = in.data();
			z.avail_in = static_cast<uInt>(f.gcount());
		}
		if (!inMember)  // between members: zeros (padding) or the next member's header
		{
			while (z.avail_in > 0 && *z.next_in == 0) ++z.next_in, --z.avail_in, padding = true;
			if (z.avail_in == 0) continue;
			if (padding) ok = false;  // data after the padding
			::inflateReset(&z);
			inMember = true;
			continue;
		}
		z.next_out = out.data();
		z.avail_out = static_cast<uInt>(out.size());
		const int r = ::inflate(&z, Z_NO_FLUSH);
		total += out.size() - z.avail_out;
		if (r == Z_STREAM_END)
			inMember = false;
		else if (r != Z_OK && r != Z_BUF_ERROR)
			ok = false;
	}
	::inflateEnd(&z);
	if (!ok || inMember) return std::nullopt;
	return total;
}
}  // namespace

uint32_t crc32Update(uint32_t crc, const void* data, size_t size)
{
	const auto* p = static_cast<const unsigned char*>(data);
	uint32_t c = crc ^ 0xFFFFFFFFu;
	for (size_t i = 0; i < size; ++i) c = kCrcTable[(c ^ p[i]) & 0xFF] ^ (c >> 8);
	return c ^ 0xFFFFFFFFu;
}

CLogInputFile::CLogInputFile(const std::string& path) : m_path(path)
{
	namespace fs = std::filesystem;
	std::error_code ec;
	if (!fs::exists(path, ec)) throw CLogReadError(path, "", "cannot open: no such file");
	if (fs::is_directory(path, ec)) throw CLogReadError(path, "", "cannot open: a directory");
	// Before any open(2): opening a FIFO for reading blocks until a writer comes.
	if (!fs::is_regular_file(path, ec))
		throw CLogReadError(
			path, "",
			"not a regular file (a FIFO, a pipe or a device?): logs are read "
			"from files, whose size gives the progress and whose gzip trailer is "
			"checked; save the stream to a file first");
	std::ifstream raw(path, std::ios::binary);
	if (!raw) throw CLogReadError(path, "", "cannot open for reading (permissions?)");
	m_fileSize = fs::file_size(path, ec);
	if (ec) throw CLogReadError(path, "", "cannot get its size: " + ec.message());

	unsigned char magic[2] = {0, 0};
	raw.read(reinterpret_cast<char*>(magic), 2);
	m_isGzip = raw.gcount() == 2 && magic[0] == 0x1f && magic[1] == 0x8b;
	if (m_isGzip)
	{
		// 10-byte header + 8-byte trailer at least.
		if (m_fileSize < 18)
			throw CLogReadError(path, "byte " + std::to_string(m_fileSize),
								"gzip file truncated: shorter than a gzip header and trailer");
		unsigned char trailer[8];
		raw.seekg(static_cast<std::streamoff>(m_fileSize - 8));
		raw.read(reinterpret_cast<char*>(trailer), 8);
		if (raw.gcount() != 8) throw CLogReadError(path, "", "cannot read the gzip trailer");
		m_trailerCrc = littleEndian32(trailer);
		m_trailerSize = littleEndian32(trailer + 4);
	}
	std::string err;
	if (!m_in.open(path, err)) throw CLogReadError(path, "", "cannot open: " + err);
}

size_t CLogInputFile::Read(void* buffer, size_t count)
{
	auto* out = static_cast<unsigned char*>(buffer);
	size_t total = 0;
	while (total < count && !m_reachedEnd)
	{
		// gzread takes an unsigned int and returns an int: keep chunks small.
		const size_t want = std::min<size_t>(count - total, size_t(1) << 30);
		const size_t got = m_in.Read(out + total, want);
		if (got > want)  // gzread returned -1: a zlib data error
		{
			m_dataError = true;
			throw CLogReadError(m_path, "byte " + std::to_string(m_position),
								"corrupt gzip data (zlib cannot inflate past this point)");
		}
		m_crc = crc32Update(m_crc, out + total, got);
		m_position += got;
		total += got;
		if (got < want) m_reachedEnd = true;
	}
	return total;
}

size_t CLogInputFile::Write(const void*, size_t)
{
	throw CLogReadError(m_path, "", "internal error: writing to an input log");
}

std::string CLogInputFile::getStreamDescription() const
{
	return "log file '" + m_path + "'";
}

double CLogInputFile::fractionRead() const
{
	if (m_reachedEnd) return 1.0;
	double total = static_cast<double>(m_fileSize);
	if (m_isGzip)
	{
		// ISIZE is the length mod 2^32: add the wraps the position proves.
		uint64_t size = m_trailerSize;
		while (size < m_position) size += uint64_t(1) << 32;
		total = static_cast<double>(size);
	}
	if (total <= 0) return 0.0;
	return std::clamp(static_cast<double>(m_position) / total, 0.0, 1.0);
}

void CLogInputFile::verifyCompleteAtEnd()
{
	std::array<unsigned char, 1 << 16> scratch;
	while (!m_reachedEnd) Read(scratch.data(), scratch.size());
	if (!m_isGzip) return;
	if (m_crc == m_trailerCrc && static_cast<uint32_t>(m_position) == m_trailerSize) return;
	// Not one member ending at the file's end: several members, or zero padding after the last,
	// are whole too if every member inflates with its CRC-32 and length and the lengths add up.
	if (inflatedLengthOfMembers(m_path) != std::optional<uint64_t>(m_position))
		throw CLogReadError(
			m_path, "byte " + std::to_string(m_position),
			"the gzip data stop here without a matching trailer (length and CRC-32 differ "
			"from those recorded at the end of the file): the file is truncated or corrupt");
}

}  // namespace lrgc::apps
