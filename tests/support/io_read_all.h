/* Header-only test helper: reads a whole log with lrgc::apps::openLog, keeping the entries,
 * the warnings, the statistics and the error that stopped it (in openLog or next()), if any.
 * Header-only because lrgc_test_support does not link lrgc_apps. */
#pragma once

#include <lrgc_apps/io/LogReader.h>

#include <optional>
#include <string>
#include <vector>

namespace lrgc::test
{
struct TReadResult
{
	std::vector<lrgc::apps::TLogEntry> entries;
	std::vector<std::string> warnings;
	lrgc::apps::TLogReadStats stats;
	std::optional<std::string> error;  //!< what() of the CLogReadError that stopped it
	std::vector<double> fractions;     //!< fractionRead() after each entry
};

inline TReadResult readWholeLog(const std::string& path,
								const lrgc::apps::TLogReaderOptions& options = {})
{
	TReadResult out;
	std::unique_ptr<lrgc::apps::CLogReader> reader;
	try
	{
		reader = lrgc::apps::openLog(path, options);
		while (auto e = reader->next())
		{
			out.entries.push_back(std::move(*e));
			out.fractions.push_back(reader->fractionRead());
		}
	}
	catch (const lrgc::apps::CLogReadError& e)
	{
		out.error = e.what();
	}
	if (!reader) return out;  // openLog failed
	out.warnings = reader->takeWarnings();
	out.stats = reader->stats();
	return out;
}

inline bool contains(const std::string& text, const std::string& part)
{
	return text.find(part) != std::string::npos;
}

inline bool anyContains(const std::vector<std::string>& texts, const std::string& part)
{
	for (const auto& t : texts)
		if (contains(t, part)) return true;
	return false;
}

}  // namespace lrgc::test
