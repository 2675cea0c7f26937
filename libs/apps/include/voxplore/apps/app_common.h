/* voxplore — small helpers shared by the app classes. */
#pragma once

#include <csignal>
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

/// @brief Exit code of an app stopped by SIGINT / SIGTERM after writing its
///        outputs (128 + SIGINT, the shell's convention for Ctrl-C).
constexpr int kExitInterrupted = 130;

/// @brief Makes the first SIGINT or SIGTERM only request a stop
///        (interruptRequested() turns true; the apps poll it between stops
///        and between robot steps, then write every output). The handler
///        re-arms the default action, so a second Ctrl-C kills at once.
///        Called by the apps' run(); execute() never installs it.
void installInterruptHandler();

/// @brief True once SIGINT / SIGTERM arrived (or requestInterrupt() was called).
///        Async-signal-safe flag (std::sig_atomic_t).
bool interruptRequested();

/// @brief Sets the flag as the signal handler does (tests, embedding code).
void requestInterrupt();

/// @brief Clears the flag (tests, or an embedding program that runs again).
void clearInterrupt();

}  // namespace voxplore::apps
