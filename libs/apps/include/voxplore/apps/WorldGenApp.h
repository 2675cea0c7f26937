/* voxplore — the voxplore-worldgen application: procedural buildings. */
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace voxplore::apps
{
/// @brief Command-line options of voxplore-worldgen.
struct WorldGenOptions
{
  uint64_t seed = 0;
  std::string out_dir;                ///< DIR: building.world, building.json, topview.png
  std::string config;                 ///< ini with [worldgen] (empty: built-in defaults)
  std::optional<std::string> layout;  ///< overrides [worldgen] layout
  bool topview = true;                ///< also write DIR/topview.png
  bool quiet = false;
};

/// @brief What was written.
struct WorldGenSummary
{
  std::string world_path, truth_path, layout;
  double floor_area_m2 = 0;
  std::size_t rooms = 0, doors = 0;
};

/// @brief voxplore-worldgen: draws a building from a seed and writes it as a
///        `.world` file that every app loads, with its ground truth beside it.
class WorldGenApp
{
 public:
  /// @brief Parses the command line (TCLAP, --help) and runs. Never throws.
  int run(int argc, const char* const* argv);

  /// @brief Runs with parsed options; the written world is loaded back and
  ///        its start checked free for the omniRob.
  /// @throws std::runtime_error on bad input (naming the file or key).
  WorldGenSummary execute(const WorldGenOptions& opts);
};

}  // namespace voxplore::apps
