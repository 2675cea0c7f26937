/* voxplore — a terminal progress line for long work. */
#pragma once

#include <chrono>
#include <cstddef>
#include <string>

namespace voxplore::common
{
/// @brief Prints "label [####....] i/n  elapsed  ETA" to stderr, throttled to
///        about 10 updates per second; silent when `enabled` is false. With
///        `total` 0 (unknown) it prints a count without bar, total or ETA:
///        "label: i UNIT  elapsed".
class Progress
{
 public:
  /// @param unit what is counted, plural ("stops"; "1 stop"), shown when `total` is 0
  Progress(std::string label, std::size_t total, bool enabled = true, std::string unit = {});
  ~Progress();
  /// @brief Sets the count done; `note` is appended to the line.
  void update(std::size_t done, const std::string& note = {});
  /// @brief Prints the final line (100% or where it stopped; `note`, else the
  ///        last update's note) with a newline; nothing when no line was ever printed.
  void finish(const std::string& note = {});

 private:
  std::string label_;
  std::size_t total_;
  std::string unit_;
  bool enabled_;
  bool finished_ = false;
  bool printed_ = false;  ///< a line is on the terminal (finish() ends it)
  std::size_t done_ = 0;
  std::string note_;  ///< the last update's note
  std::chrono::steady_clock::time_point start_, last_print_;
  void print(const std::string& note, bool force);
};

}  // namespace voxplore::common
