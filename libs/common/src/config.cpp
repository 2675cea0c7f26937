#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <voxplore/common/config.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <stdexcept>

namespace voxplore::common
{
namespace
{
// Optimal string alignment distance: edits plus adjacent transpositions
// (the typical typo "lenght" is one edit from "length").
std::size_t editDistance(const std::string& a, const std::string& b)
{
  const std::size_t n = a.size(), m = b.size();
  std::vector<std::vector<std::size_t>> d(n + 1, std::vector<std::size_t>(m + 1));
  for (std::size_t i = 0; i <= n; i++) d[i][0] = i;
  for (std::size_t j = 0; j <= m; j++) d[0][j] = j;
  for (std::size_t i = 1; i <= n; i++)
    for (std::size_t j = 1; j <= m; j++)
    {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[n][m];
}

std::string closest(const std::string& key, const std::set<std::string>& known)
{
  std::string best;
  std::size_t best_d = std::string::npos;
  for (const auto& k : known)
  {
    const auto d = editDistance(key, k);
    if (d < best_d)
    {
      best_d = d;
      best = k;
    }
  }
  return best;
}

std::set<std::string> savedKeys(const mrpt::config::CLoadableOptions& params, const std::string& s)
{
  mrpt::config::CConfigFileMemory mem;
  params.saveToConfigFile(mem, s);
  std::vector<std::string> keys;
  mem.getAllKeys(s, keys);
  return {keys.begin(), keys.end()};
}

bool parsesAsNumber(const std::string& text)
{
  std::istringstream is(text);
  double v;
  is >> v;
  if (is.fail()) return false;
  is >> std::ws;
  return is.eof();
}

std::string trim(const std::string& s)
{
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}
}  // namespace

std::string configSourceName(const mrpt::config::CConfigFileBase& cfg)
{
  if (const auto* f = dynamic_cast<const mrpt::config::CConfigFile*>(&cfg))
    return f->getAssociatedFile();
  return "<memory>";
}

void assertKnownKeys(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section,
    const std::set<std::string>& known)
{
  std::vector<std::string> keys;
  cfg.getAllKeys(section, keys);
  for (const auto& k : keys)
  {
    if (known.count(k)) continue;
    std::string msg =
        configSourceName(cfg) + ": unknown key '" + k + "' in section [" + section + "]";
    if (!known.empty()) msg += " (did you mean '" + closest(k, known) + "'?)";
    throw std::runtime_error(msg);
  }
}

void assertKnownKeys(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section,
    const mrpt::config::CLoadableOptions& params, const std::set<std::string>& extra_known)
{
  auto known = savedKeys(params, section);
  known.insert(extra_known.begin(), extra_known.end());
  assertKnownKeys(cfg, section, known);
}

void assertKnownSections(
    const mrpt::config::CConfigFileBase& cfg, const std::set<std::string>& known_sections)
{
  std::vector<std::string> sections;
  cfg.getAllSections(sections);
  for (const auto& s : sections)
  {
    if (s.empty() || known_sections.count(s)) continue;
    throw std::runtime_error(
        configSourceName(cfg) + ": unknown section [" + s + "] (did you mean [" +
        closest(s, known_sections) + "]?)");
  }
}

std::optional<bool> parseBoolWord(const std::string& text)
{
  const std::string v = trim(text);
  if (v == "true" || v == "1" || v == "yes") return true;
  if (v == "false" || v == "0" || v == "no") return false;
  return std::nullopt;
}

void assertNumericValues(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section,
    const mrpt::config::CLoadableOptions& params)
{
  mrpt::config::CConfigFileMemory mem;
  params.saveToConfigFile(mem, section);
  std::vector<std::string> keys;
  mem.getAllKeys(section, keys);
  for (const auto& k : keys)
  {
    if (!cfg.keyExists(section, k)) continue;
    const auto def = trim(mem.read_string(section, k, ""));
    const auto val = trim(cfg.read_string(section, k, ""));
    if (def == "true" || def == "false")
    {
      requireValid(parseBoolWord(val).has_value(), cfg, section, k,
                   "expected a boolean (true/false)");
    }
    else if (parsesAsNumber(def))
    {
      requireValid(parsesAsNumber(val), cfg, section, k, "expected a number");
    }
  }
}

void loadChecked(
    mrpt::config::CLoadableOptions& params, const mrpt::config::CConfigFileBase& cfg,
    const std::string& section)
{
  assertKnownKeys(cfg, section, params);
  assertNumericValues(cfg, section, params);
  params.loadFromConfigFile(cfg, section);
}

namespace
{
/// MRPT 2.5.8's CConfigFile strips a trailing "//" comment only where a
/// blank precedes it, and SimpleIni trims the blanks before a value: a key
/// left empty before its comment (`navlog_dir =   // MRPT navigation logs
/// ...`) read as the comment itself. That one made every drive write an
/// MRPT navigation log into a directory named after the comment, at the
/// file system's root (83,000 logs, 2.1 GB on the development machine by
/// the twenty-eighth session), and scan all of them for a free name: a
/// quarter of a building run's CPU. Here a value whose first non-blank
/// characters are "//" is empty.
class IniFile : public mrpt::config::CConfigFile
{
 public:
  using CConfigFile::CConfigFile;

 protected:
  std::string readString(const std::string& section, const std::string& name,
                         const std::string& default_str, bool fail_if_not_found) const override
  {
    std::string v = CConfigFile::readString(section, name, default_str, fail_if_not_found);
    return trim(v).rfind("//", 0) == 0 ? std::string() : v;
  }
};
}  // namespace

std::unique_ptr<mrpt::config::CConfigFileBase> openIniFile(const std::string& path)
{
  if (!std::filesystem::is_regular_file(path))
    throw std::runtime_error("config file not found: '" + path + "'");
  return std::make_unique<IniFile>(path);
}

std::vector<double> parseNumberList(const std::string& text, const std::string& what)
{
  std::string t = text;
  std::replace(t.begin(), t.end(), ',', ' ');
  std::istringstream is(t);
  std::vector<double> out;
  std::string tok;
  while (is >> tok)
  {
    char* end = nullptr;
    const double v = std::strtod(tok.c_str(), &end);
    if (end == tok.c_str() || *end != '\0' || !std::isfinite(v))
      throw std::runtime_error(what + ": '" + tok + "' is not a finite number");
    out.push_back(v);
  }
  return out;
}

double readDoubleStrict(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
    double default_value)
{
  if (!cfg.keyExists(section, key)) return default_value;
  const auto val = trim(cfg.read_string(section, key, ""));
  requireValid(parsesAsNumber(val), cfg, section, key, "expected a number");
  return std::stod(val);
}

double readNumberOrWord(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key,
    double default_value, const std::string& word, double word_value)
{
  if (cfg.keyExists(section, key) && trim(cfg.read_string(section, key, "")) == word)
    return word_value;
  return readDoubleStrict(cfg, section, key, default_value);
}

std::string numberOrWord(double v, const std::string& word, double word_value)
{
  return v == word_value ? word : mrpt::format("%.17g", v);
}

void requireValid(
    bool ok, const mrpt::config::CConfigFileBase& cfg, const std::string& section,
    const std::string& key, const std::string& why)
{
  if (ok) return;
  throw std::runtime_error(
      configSourceName(cfg) + ": [" + section + "] " + key + " = '" +
      trim(cfg.read_string(section, key, "")) + "': " + why);
}

std::string dumpParams(const mrpt::config::CLoadableOptions& params, const std::string& section)
{
  mrpt::config::CConfigFileMemory mem;
  params.saveToConfigFile(mem, section);
  return mem.getContent();
}

}  // namespace voxplore::common
