#include "ErrorText.h"

#include <mrpt/core/exceptions.h>

#include <algorithm>
#include <cctype>
#include <sstream>
#include <vector>

namespace lrgc::apps
{
namespace
{
// "[12] ...", "[0 ] ...": a frame of MRPT's call stack backtrace.
bool isStackFrame(const std::string& line)
{
	if (line.empty() || line[0] != '[') return false;
	size_t i = 1;
	while (i < line.size() && std::isdigit(static_cast<unsigned char>(line[i]))) ++i;
	return i > 1 && i < line.size() && (line[i] == ' ' || line[i] == ']');
}

// mrpt::internal::exception_line_msg() writes "file:line: [function] message"; the function
// (a __PRETTY_FUNCTION__) may hold brackets itself ("[with T = double]").
std::string withoutLocation(const std::string& msg)
{
	const auto open = msg.find(": [");
	if (open == std::string::npos || msg.find('\n') < open) return msg;
	int depth = 0;
	for (size_t i = open + 2; i < msg.size(); ++i)
	{
		if (msg[i] == '[')
			++depth;
		else if (msg[i] == ']' && --depth == 0)
			return msg.substr(std::min(msg.size(), msg.find_first_not_of(' ', i + 1)));
	}
	return msg;
}
}  // namespace

std::string oneLineText(const std::string& text)
{
	// Blocks: "==== MRPT exception ====" / "Message: ..." / "Location: ..." /
	// "Call stack backtrace:" / "[0 ] ..." frames; "==== non-MRPT exception ====" / the
	// message. Nested exceptions repeat the block. Kept: every line of message text.
	// A nested exception's text may follow other text on its line ("outer: " + e.what()).
	std::string t = text;
	for (const std::string banner :
		 {"==== MRPT exception ====", "==== non-MRPT exception ===="})
		for (size_t p; (p = t.find(banner)) != std::string::npos;)
			t.replace(p, banner.size(), "\n");
	std::vector<std::string> parts;
	std::istringstream in(t);
	for (std::string line; std::getline(in, line);)
	{
		const auto b = line.find_first_not_of(" \t");
		if (b == std::string::npos) continue;
		line = line.substr(b);
		while (!line.empty() && (line.back() == ' ' || line.back() == '\r')) line.pop_back();
		if (line.rfind("Message:", 0) == 0)
		{
			line = line.substr(8);
			line = line.substr(std::min(line.size(), line.find_first_not_of(' ')));
		}
		else if (line.rfind("Location:", 0) == 0 || line.rfind("Call stack", 0) == 0 ||
				 isStackFrame(line))
			continue;
		if (!line.empty() && std::find(parts.begin(), parts.end(), line) == parts.end())
			parts.push_back(line);
	}
	std::string out;
	for (const auto& p : parts) out += (out.empty() ? "" : out.back() == ':' ? " " : "; ") + p;
	if (out.empty())
	{
		out = text;
		std::replace(out.begin(), out.end(), '\n', ' ');
	}
	return out;
}

std::string oneLineError(const std::exception& e)
{
	if (const auto* m = dynamic_cast<const mrpt::ExceptionWithCallBackBase*>(&e))
		return oneLineText(withoutLocation(m->originalWhat));
	return oneLineText(e.what());
}

std::string errorDetails(const std::exception& e)
{
	return mrpt::exception_to_str(e);
}

}  // namespace lrgc::apps
