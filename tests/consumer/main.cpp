// A program outside voxplore: SlamIcpParams and OctoMapLayer (voxplore::mapping),
// DriverParams and RobotInterface (voxplore::navigation), the exploration
// loop's parameters and clock (voxplore::mission), from an installed prefix.
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <voxplore/mapping/OctoMapLayer.h>
#include <voxplore/mapping/SlamIcp.h>
#include <voxplore/mission/ExplorationLoop.h>
#include <voxplore/navigation/DriverParams.h>
#include <voxplore/navigation/RobotInterface.h>

#include <cmath>
#include <iostream>

namespace
{
// The smallest robot: stands still at the origin.
class StillRobot : public voxplore::navigation::RobotInterface
{
 public:
  void setVelocity(double, double, double) override {}
  void stop() override {}
  mrpt::poses::CPose2D pose() const override { return {}; }
  mrpt::poses::CPose2D odometry() const override { return {}; }
  mrpt::math::TTwist2D velocity() const override { return {0, 0, 0}; }
  bool obstacles(mrpt::maps::CSimplePointsMap& out) override
  {
    out.clear();
    return true;
  }
  mrpt::Clock::time_point now() const override { return mrpt::Clock::now(); }
  void step(double) override {}
};
}  // namespace

int main()
{
  voxplore::mapping::SlamIcpParams slam;
  mrpt::config::CConfigFileMemory ini;
  slam.save(ini);
  voxplore::mapping::SlamIcpParams back;
  back.load(ini);

  voxplore::mapping::OctoMapLayer layer(back.octomap);
  layer.setStartBoxFree(mrpt::poses::CPose3D());

  voxplore::navigation::DriverParams drive;
  mrpt::config::CConfigFileMemory nav;
  drive.writeMrptConfig(nav);
  StillRobot robot;
  mrpt::maps::CSimplePointsMap obstacles;

  voxplore::mission::ExplorationLoopParams limits;
  mrpt::config::CConfigFileMemory explore;
  limits.saveToConfigFile(explore, "explore");
  const voxplore::mission::SystemClock clock;

  const bool ok = layer.numLeafNodes() > 0 && robot.obstacles(obstacles) &&
                  nav.keyExists("CReactiveNavigationSystem", "PTG0_Type") &&
                  explore.keyExists("explore", "max_steps") &&
                  std::abs(mrpt::Clock::toDouble(clock.now()) -
                           mrpt::Clock::toDouble(mrpt::Clock::now())) < 1.0;
  std::cout << "voxplore consumer: " << layer.numLeafNodes()
            << " leaves in the start box, robot radius " << drive.robotRadius()
            << " m: " << (ok ? "OK" : "FAILED") << std::endl;
  return ok ? 0 : 1;
}
