/* voxplore — private helpers of the world loaders: file checks and JSON reading
 * with errors that start with the file path. Not installed. */
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

namespace voxplore::sim::detail
{
using json = nlohmann::json;

/// @brief Throws std::runtime_error("<path>: <what>").
[[noreturn]] inline void failFile(const std::string& path, const std::string& what)
{
  throw std::runtime_error(path + ": " + what);
}

/// @brief Throws naming `path` when it does not exist, is not a regular file or is empty.
inline void requireNonEmptyFile(const std::string& path)
{
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st))
  {
    failFile(path, "file does not exist");
  }
  if (!fs::is_regular_file(st))
  {
    failFile(path, "not a regular file");
  }
  if (fs::file_size(path, ec) == 0 && !ec)
  {
    failFile(path, "file is empty");
  }
}

/// @brief Parses JSON text read from `path`.
/// @throws std::runtime_error naming `path` when it is not valid JSON (with
///         nlohmann's byte position).
inline nlohmann::json parseJsonText(const std::string& text, const std::string& path)
{
  try
  {
    return nlohmann::json::parse(text);
  }
  catch (const nlohmann::json::parse_error& e)
  {
    failFile(path,
             "malformed JSON at byte " + std::to_string(e.byte) + ": " + std::string(e.what()));
  }
  catch (const nlohmann::json::exception& e)
  {
    // Not a parse_error but still malformed input, e.g. out_of_range.406 for a
    // number beyond double range ("1e400"); found by fuzz/fuzz_world_file.
    failFile(path, "malformed JSON: " + std::string(e.what()));
  }
}

/// @brief Reads a whole file as text.
/// @throws std::runtime_error naming `path` when missing, empty or unreadable.
inline std::string readTextFile(const std::string& path)
{
  requireNonEmptyFile(path);
  std::ifstream in(path, std::ios::binary);
  if (!in)
  {
    failFile(path, "cannot open for reading");
  }
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

/// @brief Reads and parses a JSON file.
/// @throws std::runtime_error naming `path` when missing, empty, unreadable or
///         not valid JSON (with nlohmann's byte position).
inline nlohmann::json readJsonFile(const std::string& path)
{
  return parseJsonText(readTextFile(path), path);
}

/// @brief Where in a file a JSON object sits, for error messages.
struct Where
{
  const std::string& path;
  std::string what;  ///< e.g. "elements[3] (table)" or "start"

  [[noreturn]] void fail(const std::string& msg) const
  {
    detail::failFile(path, what.empty() ? msg : what + ": " + msg);
  }
};

/// @brief Typed access to the fields of one JSON object; errors name the file,
///        the object (Where) and the field.
class Fields
{
 public:
  Fields(const json& obj, Where where) : obj_(obj), where_(std::move(where)) {}

  const Where& where() const { return where_; }

  /// Throws when the object holds a key outside `known`.
  void requireKnownKeys(const std::set<std::string>& known) const
  {
    for (const auto& item : obj_.items())
    {
      if (known.count(item.key()) == 0)
      {
        std::string list;
        for (const auto& k : known)
        {
          list += (list.empty() ? "" : ", ") + k;
        }
        where_.fail("unknown field '" + item.key() + "' (known: " + list + ")");
      }
    }
  }

  bool has(const char* key) const { return obj_.contains(key); }

  const json& required(const char* key) const
  {
    const auto it = obj_.find(key);
    if (it == obj_.end())
    {
      where_.fail(std::string("missing required field '") + key + "'");
    }
    return *it;
  }

  double number(const char* key) const
  {
    const json& v = required(key);
    if (!v.is_number())
    {
      where_.fail(std::string("field '") + key + "' must be a number, got " + v.dump());
    }
    return v.get<double>();
  }

  double number(const char* key, double default_value) const
  {
    return has(key) ? number(key) : default_value;
  }

  double positive(const char* key, double default_value) const
  {
    const double v = number(key, default_value);
    if (!(v > 0))
    {
      where_.fail(std::string("field '") + key + "' must be > 0, got " + std::to_string(v));
    }
    return v;
  }

  double positive(const char* key) const { return positive(key, number(key)); }

  template <int N>
  Eigen::Matrix<float, N, 1> vector(const char* key) const
  {
    const json& v = required(key);
    Eigen::Matrix<float, N, 1> out;
    if (!v.is_array() || v.size() != static_cast<std::size_t>(N))
    {
      where_.fail(std::string("field '") + key + "' must be an array of " + std::to_string(N) +
                  " numbers, got " + v.dump());
    }
    for (int i = 0; i < N; ++i)
    {
      if (!v[static_cast<std::size_t>(i)].is_number())
      {
        where_.fail(std::string("field '") + key + "' must be an array of " + std::to_string(N) +
                    " numbers, got " + v.dump());
      }
      out[i] = v[static_cast<std::size_t>(i)].get<float>();
    }
    return out;
  }

  template <int N>
  Eigen::Matrix<float, N, 1> vector(const char* key, const Eigen::Matrix<float, N, 1>& def) const
  {
    return has(key) ? vector<N>(key) : def;
  }

  std::string string(const char* key) const
  {
    const json& v = required(key);
    if (!v.is_string())
    {
      where_.fail(std::string("field '") + key + "' must be a string, got " + v.dump());
    }
    return v.get<std::string>();
  }

  bool boolean(const char* key, bool default_value) const
  {
    if (!has(key))
    {
      return default_value;
    }
    const json& v = obj_.at(key);
    if (!v.is_boolean())
    {
      where_.fail(std::string("field '") + key + "' must be true or false, got " + v.dump());
    }
    return v.get<bool>();
  }

 private:
  const json& obj_;
  Where where_;
};

}  // namespace voxplore::sim::detail
