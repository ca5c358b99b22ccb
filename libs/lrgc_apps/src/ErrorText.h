/* Errors for people: one line per error, the details for --verbose.
 *
 * MRPT's exceptions (THROW_EXCEPTION, ASSERT_) carry "file:line: [function] " before their
 * message, and their what() and mrpt::exception_to_str() wrap it in a
 * "==== MRPT exception ====" banner with the call stack; exception_to_str() wraps any other
 * exception in "==== non-MRPT exception ====". A user needs the message; a developer the
 * rest, which errorDetails() keeps for lrgc-slam --verbose.
 */
#pragma once

#include <exception>
#include <string>

namespace lrgc::apps
{
/** The message of `e` on one line: for an MRPT exception its original message without the
 * source location and call stack; a banner, "Location:" and stack lines in the text (of
 * nested exceptions) are dropped; line breaks become "; ". */
std::string oneLineError(const std::exception& e);

/** An exception or log text on one line: every line of message text, without MRPT's
 * banners, "Location:" lines and call stacks; lines joined by "; " (by " " after a ':'). */
std::string oneLineText(const std::string& text);

/** Everything known about `e`: MRPT's banner, the source location and the call stack. */
std::string errorDetails(const std::exception& e);

}  // namespace lrgc::apps
