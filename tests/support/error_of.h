/* The message of the exception a call throws, for tests of error texts. */
#pragma once

#include <mrpt/core/exceptions.h>

#include <exception>
#include <functional>
#include <string>

namespace lrgc::test
{
/** mrpt::exception_to_str of what f throws, or "" if it throws nothing. */
inline std::string errorOf(const std::function<void()>& f)
{
	try
	{
		f();
	}
	catch (const std::exception& e)
	{
		return mrpt::exception_to_str(e);
	}
	return "";
}
}  // namespace lrgc::test
