/* voxplore tests — an error that must name what is wrong. */
#pragma once

#include <gtest/gtest.h>

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
}  // namespace voxplore::test
