#include <voxplore/common/Progress.h>

#include <cstdio>

namespace voxplore::common
{
Progress::Progress(std::string label, std::size_t total, bool enabled)
    : label_(std::move(label)), total_(total), enabled_(enabled)
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
  print(note, false);
}

void Progress::finish(const std::string& note)
{
  if (finished_) return;
  print(note, true);
  if (enabled_) std::fputc('\n', stderr);
  finished_ = true;
}

void Progress::print(const std::string& note, bool force)
{
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (!force && now - last_print_ < std::chrono::milliseconds(100)) return;
  last_print_ = now;
  const double frac = total_ > 0 ? std::min(1.0, double(done_) / double(total_)) : 1.0;
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(frac * kWidth);
  char bar[kWidth + 1];
  for (int i = 0; i < kWidth; i++) bar[i] = i < filled ? '#' : '.';
  bar[kWidth] = '\0';
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double eta = frac > 1e-9 ? elapsed * (1.0 - frac) / frac : 0.0;
  std::fprintf(
      stderr, "\r%s [%s] %zu/%zu  %.1fs  ETA %.1fs  %s\033[K", label_.c_str(), bar, done_, total_,
      elapsed, eta, note.c_str());
  std::fflush(stderr);
}

}  // namespace voxplore::common
