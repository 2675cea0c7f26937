/* voxplore tests — ini keys: an error that must name what is wrong, and
 * what a key is saved as. */
#pragma once

#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/config/CLoadableOptions.h>

#include <exception>
#include <string>

namespace voxplore::test
{
/// @brief Runs `load` (which must throw) and checks that the message names
///        `key`; `what` says what was wrongly accepted when it does not throw.
template <class Load>
void expectErrorNaming(Load&& load, const std::string& key, const std::string& what)
{
  try
  {
    load();
    ADD_FAILURE() << what << " was accepted";
  }
  catch (const std::exception& e)
  {
    EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
  }
}

/// @brief The text `params` saves for [section] key (e.g. "auto").
inline std::string savedText(const mrpt::config::CLoadableOptions& params,
                             const std::string& section, const std::string& key)
{
  mrpt::config::CConfigFileMemory saved;
  params.saveToConfigFile(saved, section);
  return saved.read_string(section, key, "");
}

}  // namespace voxplore::test
