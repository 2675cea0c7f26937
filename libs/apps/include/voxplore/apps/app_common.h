/* voxplore — small helpers shared by the app classes. */
#pragma once

#include <functional>
#include <string>

namespace voxplore::apps
{
/// @brief Runs `body`, printing any exception as "<app>: error: <what>" to
///        stderr. @return body's exit code, or 1 after an exception.
int runGuarded(const std::string& app_name, const std::function<int()>& body);

/// @brief Exit code after TCLAP's parse() returned false: 0 when the user
///        asked for --help / --version, 1 for a command-line error.
int exitCodeAfterFailedParse(int argc, const char* const* argv);

/// @brief Creates `dir` (and parents) and checks it is writable.
/// @throws std::runtime_error naming the directory otherwise.
void prepareOutputDir(const std::string& dir);

}  // namespace voxplore::apps
