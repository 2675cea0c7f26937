/* voxplore — parameter loading helpers shared by every library.
 *
 * Parameters structs derive from mrpt::config::CLoadableOptions; the field
 * name is the ini key. These helpers add what MRPT's loader lacks: unknown
 * (misspelt) keys are an error naming the key and the file, and values that
 * do not parse are an error instead of a silent 0. */
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/config/CLoadableOptions.h>

#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace voxplore::common
{
/// @brief Human-readable name of a config source: the file path for a
///        CConfigFile, "<memory>" otherwise.
std::string configSourceName(const mrpt::config::CConfigFileBase& cfg);

/// @brief Throws when `section` of `cfg` holds a key that `params` does not
///        save (i.e. a key the struct does not know). The message names the
///        file, the section, the key and the closest known key.
/// @param extra_known keys accepted besides the ones `params` saves.
void assertKnownKeys(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section,
    const mrpt::config::CLoadableOptions& params,
    const std::set<std::string>& extra_known = {});

/// @brief Throws when any key of `section` in `cfg` is not in `known`.
void assertKnownKeys(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section,
    const std::set<std::string>& known);

/// @brief Throws when `cfg` holds a section not in `known_sections`.
void assertKnownSections(
    const mrpt::config::CConfigFileBase& cfg, const std::set<std::string>& known_sections);

/// @brief Loads params from `section` and validates keys first.
void loadChecked(
    mrpt::config::CLoadableOptions& params, const mrpt::config::CConfigFileBase& cfg,
    const std::string& section);

/// @brief Opens an ini file; throws naming the path when it does not exist.
std::unique_ptr<mrpt::config::CConfigFileBase> openIniFile(const std::string& path);

/// @brief Parses a whitespace/comma separated list of numbers.
/// @throws std::runtime_error naming `what` when a token is not a number.
std::vector<double> parseNumberList(const std::string& text, const std::string& what);

/// @brief An ini boolean word (surrounding blanks ignored): true for true / 1
///        / yes, false for false / 0 / no, nothing for anything else.
std::optional<bool> parseBoolWord(const std::string& text);

/// @brief Reads a double key strictly: missing -> default, unparsable -> throw
///        naming file, section and key.
double readDoubleStrict(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section,
    const std::string& key, double default_value);

/// @brief readDoubleStrict, or `word_value` where the key says `word` (e.g.
///        "auto" for a sentinel the caller resolves later).
double readNumberOrWord(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section,
    const std::string& key, double default_value, const std::string& word, double word_value);

/// @brief The ini text of readNumberOrWord's value: `word` for `word_value`,
///        else the number at full precision.
std::string numberOrWord(double v, const std::string& word, double word_value);

/// @brief Throws "<source>: [section] key = value: <why>" when !ok.
void requireValid(
    bool ok, const mrpt::config::CConfigFileBase& cfg, const std::string& section,
    const std::string& key, const std::string& why);

/// @brief All parameters of `params` as ini text under `section` (for printing).
std::string dumpParams(const mrpt::config::CLoadableOptions& params, const std::string& section);

/// @brief Strict numeric-value check of every key `params` knows in `section`:
///        a key whose saved default is numeric must hold a number in `cfg`.
void assertNumericValues(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section,
    const mrpt::config::CLoadableOptions& params);

}  // namespace voxplore::common
