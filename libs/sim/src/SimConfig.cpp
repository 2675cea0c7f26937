#include <mrpt/config/CConfigFileMemory.h>
#include <voxplore/common/config.h>
#include <voxplore/sim/SimConfig.h>

#include <cmath>
#include <sstream>

namespace voxplore::sim
{
SimConfig SimConfig::defaults(const std::string& profile)
{
  SimConfig c;
  c.robot = RobotParams::byName(profile);
  c.cameras.mounts = CameraRigParams::ringAround(
      c.robot.length_m, c.robot.width_m, c.robot.camera_height_m, c.cameras.vfov);
  return c;
}

SimConfig SimConfig::load(
    const mrpt::config::CConfigFileBase& cfg, const std::optional<std::string>& profile)
{
  const std::string prof =
      profile ? *profile : cfg.read_string("robot", "profile", "omnirob", false);
  SimConfig c = defaults(prof == "custom" ? "omnirob" : prof);
  const RobotParams base = c.robot;  // the profile's, before the ini's keys
  common::loadChecked(c.robot, cfg, "robot");
  if (profile) c.robot.profile = *profile;
  if (profile && prof != "custom")
  {
    const std::pair<const char*, double RobotParams::*> body[] = {
        {"length_m", &RobotParams::length_m},
        {"width_m", &RobotParams::width_m},
        {"height_m", &RobotParams::height_m},
        {"camera_height_m", &RobotParams::camera_height_m}};
    for (const auto& [key, field] : body)
      if (std::abs(c.robot.*field - base.*field) > 1e-9)
      {
        std::ostringstream o;
        o << key << " = " << c.robot.*field << " (" << prof << ": " << base.*field << ")";
        c.profile_overridden.push_back(o.str());
      }
  }

  // camN_pose keys for any N are known; which ones are required depends on num_cameras.
  std::set<std::string> cam_keys;
  for (int i = 0; i < 256; i++) cam_keys.insert("cam" + std::to_string(i) + "_pose");
  common::assertKnownKeys(cfg, "cameras", c.cameras, cam_keys);
  common::assertNumericValues(cfg, "cameras", c.cameras);
  bool explicit_poses = false;
  for (const auto& k : cam_keys) explicit_poses = explicit_poses || cfg.keyExists("cameras", k);
  c.cameras.loadFromConfigFile(cfg, "cameras");
  if (!explicit_poses)
    c.cameras.mounts = CameraRigParams::ringAround(
        c.robot.length_m, c.robot.width_m, c.robot.camera_height_m, c.cameras.vfov);
  common::requireValid(
      static_cast<int>(c.cameras.mounts.size()) == c.cameras.num_cameras, cfg, "cameras",
      "num_cameras", "the default ring has 8 cameras: give camN_pose for every camera");

  common::loadChecked(c.sim, cfg, "simulator");
  return c;
}

std::string SimConfig::profileOverrideWarning(const std::string& ini_path) const
{
  if (profile_overridden.empty()) return {};
  std::ostringstream o;
  o << "--robot " << robot.profile << ", but [robot] in " << ini_path << " sets";
  for (const auto& k : profile_overridden) o << " " << k << ";";
  o << " the ini wins: the robot simulated has its values (leave only 'profile' in [robot], as "
       "config/explore.ini does, to simulate the profile)";
  return o.str();
}

void SimConfig::save(mrpt::config::CConfigFileBase& cfg) const
{
  robot.saveToConfigFile(cfg, "robot");
  cameras.saveToConfigFile(cfg, "cameras");
  sim.saveToConfigFile(cfg, "simulator");
}

}  // namespace voxplore::sim
