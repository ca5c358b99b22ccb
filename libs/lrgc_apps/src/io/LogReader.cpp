#include "lrgc_apps/io/LogReader.h"

#include "io/CarmenReader.h"
#include "io/LogInputFile.h"
#include "io/RawlogReader.h"

#include <mrpt/core/format.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <set>

namespace lrgc::apps
{
CLogReadError::CLogReadError(const std::string& file, const std::string& place,
							 const std::string& problem)
	: std::runtime_error(file + (place.empty() ? "" : ": " + place) + ": " + problem),
	  m_file(file),
	  m_place(place)
{
}

CLogReader::CLogReader(std::string path) : m_path(std::move(path)) {}
CLogReader::~CLogReader() = default;

std::vector<std::string> CLogReader::takeWarnings()
{
	std::vector<std::string> out;
	out.swap(m_warnings);
	return out;
}

namespace
{
const char* problemName(size_t kind)
{
	static const char* names[] = {"malformed lines", "scans with bad ranges", "empty scans",
								  "backward time jumps", "other problems"};
	return names[kind];
}
}  // namespace

void CLogReader::warn(Problem kind, const std::string& place, const std::string& what)
{
	const auto k = static_cast<size_t>(kind);
	const size_t n = ++m_problemCounts[k];
	++m_stats.warnings;
	if (n > kListedPerProblem) return;
	std::string msg = m_path + (place.empty() ? "" : ": " + place) + ": " + what;
	if (n == kListedPerProblem)
		msg += std::string(" (further ") + problemName(k) + " are counted, not listed)";
	m_warnings.push_back(std::move(msg));
}

void CLogReader::reportUnlistedWarnings()
{
	for (size_t k = 0; k < m_problemCounts.size(); ++k)
	{
		const size_t n = m_problemCounts[k];
		if (n <= kListedPerProblem) continue;
		std::string msg = mrpt::format("%s: %zu more %s not listed (%zu in all", m_path.c_str(),
									   n - kListedPerProblem, problemName(k), n);
		if (k == static_cast<size_t>(Problem::TimeBackwards))
			msg += mrpt::format(
				": %zu between scans, %zu between other messages; the largest %.3f s",
				m_stats.scanTimeJumpsBack, m_stats.otherTimeJumpsBack,
				m_stats.largestTimeJumpBack);
		m_warnings.push_back(msg + ")");
		m_problemCounts[k] = kListedPerProblem;  // reported once
	}
}

void CLogReader::checkTimeOrder(const std::string& stream, mrpt::Clock::time_point t,
								const std::string& place, bool isScan)
{
	auto [it, inserted] = m_lastTimes.try_emplace(stream, TStreamTime{t, place});
	if (inserted) return;
	if (t < it->second.time)
	{
		const double back = mrpt::Clock::toDouble(it->second.time) - mrpt::Clock::toDouble(t);
		++(isScan ? m_stats.scanTimeJumpsBack : m_stats.otherTimeJumpsBack);
		m_stats.largestTimeJumpBack = std::max(m_stats.largestTimeJumpBack, back);
		warn(Problem::TimeBackwards, place,
			 mrpt::format(
				 "%s timestamp %.6f is %.6f s earlier than the previous one (%s); kept in "
				 "file order",
				 stream.c_str(), mrpt::Clock::toDouble(t), back, it->second.place.c_str()));
	}
	it->second = TStreamTime{t, place};
}

size_t CLogReader::markBadRangesInvalid(mrpt::obs::CObservation2DRangeScan& scan,
										const std::string& place)
{
	size_t bad = 0, first = 0;
	for (size_t i = 0; i < scan.getScanSize(); ++i)
	{
		const float r = scan.getScanRange(i);
		if (!scan.getScanRangeValidity(i) || (std::isfinite(r) && r >= 0)) continue;
		if (bad++ == 0) first = i;
		scan.setScanRangeValidity(i, false);
	}
	if (bad == 0) return 0;
	m_stats.invalidRanges += bad;
	warn(Problem::BadRanges, place,
		 mrpt::format(
			 "%zu NaN, infinite or negative range(s) of %zu in scan '%s' marked invalid "
			 "(first: beam %zu)",
			 bad, scan.getScanSize(), scan.sensorLabel.c_str(), first));
	return bad;
}

// ---------------------------------------------------------------- format detection
namespace
{
constexpr size_t kDetectChunk = 16 * 1024;
constexpr size_t kDetectMax = 1024 * 1024;

// An MRPT archive starts with an object header: one byte holding the class name length
// (high bit set in the current format, clear in the old one), then the name, an identifier.
bool looksLikeMrptArchive(const std::string& b)
{
	if (b.empty()) return false;
	const auto first = static_cast<unsigned char>(b[0]);
	const size_t len = first & 0x7F;
	// A file cut inside the first class name still counts (the reader reports the cut).
	if (len < 2 || b.size() < 2) return false;
	if (!(first & 0x80) && b[1] != 'C') return false;
	if (!std::isalpha(static_cast<unsigned char>(b[1]))) return false;
	for (size_t i = 1; i <= len && i < b.size(); ++i)
	{
		const auto c = static_cast<unsigned char>(b[i]);
		if (!std::isalnum(c) && c != '_' && c != ':') return false;
	}
	return true;
}

const std::string kUtf8Bom = "\xEF\xBB\xBF";

enum class TextVerdict
{
	Carmen,
	NotCarmen,
	Undecided
};

// CARMEN: comment lines, then messages whose first word is an upper-case identifier; it is
// ours once a FLASER, RLASER, ROBOTLASER1 or ODOM line appears.
TextVerdict judgeCarmenText(const std::string& b, bool complete, std::string& why)
{
	static const std::set<std::string> ours = {"FLASER", "RLASER", "ROBOTLASER1", "ODOM"};
	if (b.find('\0') != std::string::npos)
	{
		why = "binary data (NUL bytes) that is no MRPT archive";
		return TextVerdict::NotCarmen;
	}
	// A UTF-8 byte order mark (an editor's) is no part of the first line.
	size_t pos = b.rfind(kUtf8Bom, 0) == 0 ? kUtf8Bom.size() : 0, lineNo = 0;
	while (pos < b.size())
	{
		size_t end = b.find('\n', pos);
		if (end == std::string::npos)
		{
			if (!complete) break;  // partial line: wait for more
			end = b.size();
		}
		++lineNo;
		const std::string line = b.substr(pos, end - pos);
		pos = end + 1;
		const size_t s = line.find_first_not_of(" \t\r");
		if (s == std::string::npos || line[s] == '#') continue;
		const size_t e = line.find_first_of(" \t\r", s);
		const std::string word = line.substr(s, e == std::string::npos ? e : e - s);
		if (ours.count(word)) return TextVerdict::Carmen;
		const bool identifier = std::all_of(
			word.begin(), word.end(),
			[](unsigned char c) { return std::isupper(c) || std::isdigit(c) || c == '_'; });
		if (!identifier)
		{
			why = mrpt::format("line %zu starts with '%.40s', which is no CARMEN message",
							   lineNo, word.c_str());
			return TextVerdict::NotCarmen;
		}
	}
	if (complete || b.size() >= kDetectMax)
	{
		why = mrpt::format("no FLASER, RLASER, ROBOTLASER1 or ODOM line in its first %zu bytes",
						   b.size());
		return TextVerdict::NotCarmen;
	}
	return TextVerdict::Undecided;
}
}  // namespace

LogFormat detectLogFormat(const std::string& path)
{
	CLogInputFile in(path);
	std::string head;
	bool complete = false;
	while (true)
	{
		const size_t old = head.size();
		head.resize(old + kDetectChunk);
		try
		{
			head.resize(old + in.Read(&head[old], kDetectChunk));
		}
		catch (const CLogReadError&)
		{
			// Damage further on: judge by what was readable; the reader reports the damage.
			head.resize(old);
			if (old == 0) throw;
			complete = true;
		}
		complete = complete || in.reachedEnd() || head.size() >= kDetectMax;
		if (head.empty())
		{
			in.verifyCompleteAtEnd();  // a gzip file cut before any data: say so
			throw CLogReadError(
				path, "", in.isGzip() ? "empty log (gzip file without data)" : "empty file");
		}
		if (looksLikeMrptArchive(head)) return LogFormat::MrptRawlog;
		std::string why;
		const TextVerdict v = judgeCarmenText(head, complete, why);
		if (v == TextVerdict::Carmen) return LogFormat::Carmen;
		if (v == TextVerdict::NotCarmen)
			throw CLogReadError(
				path, "",
				"unknown log format: not an MRPT rawlog (no serialized object at byte 0) "
				"nor a CARMEN log (" +
					why + ")");
	}
}

std::unique_ptr<CLogReader> openLog(const std::string& path, const TLogReaderOptions& options)
{
	switch (detectLogFormat(path))
	{
		case LogFormat::MrptRawlog:
			return std::make_unique<CRawlogReader>(path);
		case LogFormat::Carmen:
			return std::make_unique<CCarmenReader>(path, options);
	}
	throw CLogReadError(path, "", "internal error: unhandled log format");
}

}  // namespace lrgc::apps
