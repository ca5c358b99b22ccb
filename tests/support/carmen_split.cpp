#include "carmen_split.h"

#include <mrpt/core/exceptions.h>
#include <mrpt/io/CFileGZInputStream.h>

#include <fstream>
#include <vector>

namespace lrgc::test
{
TSplitCounts splitCarmenLog(const std::string& log, const std::string& firstOut,
							const std::string& secondOut)
{
	mrpt::io::CFileGZInputStream in;
	if (!in.open(log)) THROW_EXCEPTION_FMT("cannot open '%s'", log.c_str());
	std::string text;
	char buf[1 << 16];
	for (size_t n; (n = in.Read(buf, sizeof(buf))) > 0;) text.append(buf, n);
	std::vector<std::string> header, data;
	for (size_t pos = 0; pos < text.size();)
	{
		size_t end = text.find('\n', pos);
		if (end == std::string::npos) end = text.size();
		std::string line = text.substr(pos, end - pos);
		pos = end + 1;
		if (line.empty()) continue;
		(line[0] == '#' || line.rfind("PARAM", 0) == 0 ? header : data)
			.push_back(std::move(line));
	}
	if (data.empty()) THROW_EXCEPTION_FMT("'%s' holds no data line", log.c_str());
	const size_t half = data.size() / 2;
	std::ofstream a(firstOut), b(secondOut);
	for (const auto& h : header) a << h << '\n', b << h << '\n';
	for (size_t i = 0; i < data.size(); ++i) (i < half ? a : b) << data[i] << '\n';
	if (!a || !b)
		THROW_EXCEPTION_FMT("cannot write '%s' or '%s'", firstOut.c_str(), secondOut.c_str());
	return {header.size(), half, data.size() - half};
}

}  // namespace lrgc::test
