/* voxplore — the simulator's whole configuration ([robot], [cameras], [simulator]). */
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <voxplore/sim/DepthCameraRig.h>
#include <voxplore/sim/Robot.h>
#include <voxplore/sim/Simulator.h>

#include <optional>
#include <string>
#include <vector>

namespace voxplore::sim
{
/// @brief Robot, cameras and simulator settings as one unit.
struct SimConfig
{
  RobotParams robot;
  CameraRigParams cameras;
  SimulatorParams sim;
  /// The body keys ([robot] length_m, width_m, height_m, camera_height_m)
  /// that the ini set to other values than the profile given to load():
  /// "key = value (profile: value)". The ini wins; a tool should say so
  /// (config/sim.ini sets the omniRob's body, so `--robot compact` with it
  /// simulates the omniRob).
  std::vector<std::string> profile_overridden;

  /// @brief What a tool loading `ini_path` with a --robot profile should
  ///        print when profile_overridden is not empty ("" otherwise): the
  ///        keys, both values, and how to simulate the profile instead.
  std::string profileOverrideWarning(const std::string& ini_path) const;

  /// @brief Loads [robot], [cameras], [simulator] from `cfg` (keys checked:
  ///        unknown keys and non-numbers are errors naming file and key).
  ///        `profile` (omnirob | compact), when given, replaces [robot]
  ///        profile as the base the ini keys override. Unless the ini lists
  ///        camN_pose keys, the camera ring is placed around the robot's footprint.
  static SimConfig load(
      const mrpt::config::CConfigFileBase& cfg, const std::optional<std::string>& profile = {});

  /// @brief The defaults for a robot profile (camera ring around its footprint).
  static SimConfig defaults(const std::string& profile = "omnirob");

  /// @brief Writes all three sections.
  void save(mrpt::config::CConfigFileBase& cfg) const;
};

}  // namespace voxplore::sim
