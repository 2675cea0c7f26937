#include <voxplore/common/Progress.h>

#include <algorithm>
#include <cstdio>

namespace voxplore::common
{
Progress::Progress(std::string label, std::size_t total, bool enabled, std::string unit)
    : label_(std::move(label)), total_(total), unit_(std::move(unit)), enabled_(enabled)
{
  start_ = std::chrono::steady_clock::now();
  last_print_ = start_ - std::chrono::seconds(1);
}

Progress::~Progress()
{
  if (!finished_) finish();
}

void Progress::update(std::size_t done, const std::string& note)
{
  done_ = done;
  note_ = note;
  print(note, false);
}

void Progress::finish(const std::string& note)
{
  if (finished_) return;
  finished_ = true;
  if (!printed_) return;  // never shown: nothing to end (an error then stands alone)
  print(note.empty() ? note_ : note, true);
  std::fputc('\n', stderr);
}

void Progress::print(const std::string& note, bool force)
{
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (!force && now - last_print_ < std::chrono::milliseconds(100)) return;
  last_print_ = now;
  printed_ = true;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  if (total_ == 0)  // unknown total: a count, no bar, no "i/0", no ETA
  {
    std::string unit = unit_;
    if (done_ == 1 && unit.size() > 1 && unit.back() == 's') unit.pop_back();  // "1 stop"
    std::fprintf(stderr, "\r%s: %zu%s%s  %.1fs  %s\033[K", label_.c_str(), done_,
                 unit.empty() ? "" : " ", unit.c_str(), elapsed, note.c_str());
    std::fflush(stderr);
    return;
  }
  const double frac = std::min(1.0, double(done_) / double(total_));
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(frac * kWidth);
  char bar[kWidth + 1];
  for (int i = 0; i < kWidth; i++) bar[i] = i < filled ? '#' : '.';
  bar[kWidth] = '\0';
  const double eta = frac > 1e-9 ? elapsed * (1.0 - frac) / frac : 0.0;
  std::fprintf(
      stderr, "\r%s [%s] %zu/%zu  %.1fs  ETA %.1fs  %s\033[K", label_.c_str(), bar, done_, total_,
      elapsed, eta, note.c_str());
  std::fflush(stderr);
}

}  // namespace voxplore::common
