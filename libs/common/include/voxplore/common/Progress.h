/* voxplore — a terminal progress line for long work. */
#pragma once

#include <chrono>
#include <cstddef>
#include <string>

namespace voxplore::common
{
/// @brief Prints "label [####....] i/n  elapsed  ETA" to stderr, throttled to
///        about 10 updates per second; silent when `enabled` is false.
class Progress
{
 public:
  Progress(std::string label, std::size_t total, bool enabled = true);
  ~Progress();
  /// @brief Sets the count done; `note` is appended to the line.
  void update(std::size_t done, const std::string& note = {});
  /// @brief Prints the final line (100% or where it stopped) with a newline.
  void finish(const std::string& note = {});

 private:
  std::string label_;
  std::size_t total_;
  bool enabled_;
  bool finished_ = false;
  std::size_t done_ = 0;
  std::chrono::steady_clock::time_point start_, last_print_;
  void print(const std::string& note, bool force);
};

}  // namespace voxplore::common
