/* voxplore-bench — aligned text tables for stdout and the same rows as CSV,
 * shared by every voxplore-bench table. */
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace voxplore::bench
{
/// @brief One column: the heading printed on stdout and the CSV field name.
struct Column
{
  std::string title;     ///< human-readable heading (may hold a unit)
  std::string csv_name;  ///< snake_case CSV header
};

/// @brief A table printed with right-aligned columns and written as CSV.
class TextTable
{
 public:
  explicit TextTable(std::vector<Column> columns);

  /// @brief Appends a row; it must have one cell per column.
  /// @throws std::invalid_argument when the cell count differs.
  void addRow(std::vector<std::string> cells);

  /// @brief The table with a heading line, a rule and one line per row.
  std::string str() const;

  /// @brief Writes the header (csv_name) and the rows to `path`.
  /// @throws std::runtime_error naming the path when it cannot be written.
  void writeCsv(const std::string& path) const;

 private:
  std::vector<Column> columns_;
  std::vector<std::vector<std::string>> rows_;
};

/// @brief `value` with `decimals` digits after the point.
std::string fixed(double value, int decimals);

/// @brief fixed(*value, decimals), or "-" when there is no value.
std::string fixedOr(const std::optional<double>& value, int decimals);

/// @brief The CPU model from /proc/cpuinfo ("unknown CPU" when unreadable).
std::string cpuModel();

/// @brief Number of CPUs this process may run on (1 under `taskset -c 1`).
int allowedCpus();

/// @brief Local date and time as "YYYY-MM-DD HH:MM".
std::string nowString();

}  // namespace voxplore::bench
