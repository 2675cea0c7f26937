#include "bench_table.h"

#include <algorithm>
#include <ctime>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <thread>

#ifdef __linux__
#include <sched.h>
#endif

namespace voxplore::bench
{
TextTable::TextTable(std::vector<Column> columns) : columns_(std::move(columns)) {}

void TextTable::addRow(std::vector<std::string> cells)
{
  if (cells.size() != columns_.size())
    throw std::invalid_argument("TextTable::addRow: " + std::to_string(cells.size()) +
                                " cells for " + std::to_string(columns_.size()) + " columns");
  rows_.push_back(std::move(cells));
}

std::string TextTable::str() const
{
  std::vector<std::size_t> width(columns_.size());
  for (std::size_t c = 0; c < columns_.size(); c++)
  {
    width[c] = columns_[c].title.size();
    for (const auto& r : rows_) width[c] = std::max(width[c], r[c].size());
  }
  std::ostringstream os;
  const auto line = [&](const auto& cellOf)
  {
    for (std::size_t c = 0; c < columns_.size(); c++)
      os << (c ? "  " : "") << std::setw(static_cast<int>(width[c])) << cellOf(c);
    os << "\n";
  };
  line([&](std::size_t c) { return columns_[c].title; });
  line([&](std::size_t c) { return std::string(width[c], '-'); });
  for (const auto& r : rows_) line([&](std::size_t c) { return r[c]; });
  return os.str();
}

void TextTable::writeCsv(const std::string& path) const
{
  std::ofstream f(path);
  if (!f) throw std::runtime_error("cannot write '" + path + "'");
  for (std::size_t c = 0; c < columns_.size(); c++) f << (c ? "," : "") << columns_[c].csv_name;
  f << "\n";
  for (const auto& r : rows_)
  {
    for (std::size_t c = 0; c < r.size(); c++) f << (c ? "," : "") << (r[c] == "-" ? "" : r[c]);
    f << "\n";
  }
  if (!f) throw std::runtime_error("write failed: '" + path + "'");
}

std::string fixed(double value, int decimals)
{
  std::ostringstream os;
  os << std::fixed << std::setprecision(decimals) << value;
  return os.str();
}

std::string fixedOr(const std::optional<double>& value, int decimals)
{
  return value ? fixed(*value, decimals) : std::string("-");
}

std::string cpuModel()
{
  std::ifstream f("/proc/cpuinfo");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("model name", 0) == 0)
    {
      const auto colon = line.find(':');
      if (colon != std::string::npos) return line.substr(line.find_first_not_of(" \t", colon + 1));
    }
  return "unknown CPU";
}

int allowedCpus()
{
#ifdef __linux__
  cpu_set_t set;
  if (sched_getaffinity(0, sizeof(set), &set) == 0) return CPU_COUNT(&set);
#endif
  return static_cast<int>(std::thread::hardware_concurrency());
}

std::string nowString()
{
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  localtime_r(&t, &tm);
  std::ostringstream os;
  os << std::put_time(&tm, "%Y-%m-%d %H:%M");
  return os.str();
}

}  // namespace voxplore::bench
