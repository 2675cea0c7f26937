// Tests: SlamIcp fed by the simulated 8-camera rig along a tour of true poses.
#pragma once

#include <mrpt/obs/CSensoryFrame.h>
#include <voxplore/mapping/SlamIcp.h>
#include <voxplore/sim/DepthCameraRig.h>
#include <voxplore/sim/RayCaster.h>

#include <functional>
#include <random>
#include <vector>

namespace voxplore::test
{
/// Whether stop `stop` keeps camera `obs` (a camera dropped from a stop's
/// sensory frame, e.g. to leave part of the scene unmapped).
using CameraFilter = std::function<bool(std::size_t stop, const mrpt::obs::CObservation3DRangeScan& obs)>;

/// Scans the default rig (noise on) at each true pose and feeds stop i to a
/// SlamIcp with params, odometry reading odometry[i] and timestamp i [s];
/// returns its reports. rng goes on from where the caller left it.
inline std::vector<mapping::StopReport> runSlamTour(const sim::RayCaster& caster,
                                                    const mapping::SlamIcpParams& params,
                                                    const std::vector<mrpt::poses::CPose2D>& truth,
                                                    const std::vector<mrpt::poses::CPose2D>& odometry,
                                                    std::mt19937_64& rng, const CameraFilter& keep_camera = {})
{
  sim::DepthCameraRig rig{sim::CameraRigParams{}};
  mapping::SlamIcp slam(params);
  for (std::size_t i = 0; i < truth.size(); i++)
  {
    mrpt::obs::CSensoryFrame sf;
    for (const auto& o :
         rig.scan(caster, mrpt::poses::CPose3D(truth[i]), mrpt::Clock::fromDouble(double(i)), rng, true))
      if (!keep_camera || keep_camera(i, *o)) sf.insert(o);
    slam.processStop(sf, odometry.at(i), mrpt::Clock::fromDouble(double(i)));
  }
  return slam.reports();
}

/// Odometry readings along `truth` (relative to its first pose), with
/// `error` composed in front from stop `from` on (in the odometry frame).
inline std::vector<mrpt::poses::CPose2D> odometryWithError(const std::vector<mrpt::poses::CPose2D>& truth,
                                                           const mrpt::poses::CPose2D& error, std::size_t from)
{
  std::vector<mrpt::poses::CPose2D> odo;
  for (std::size_t i = 0; i < truth.size(); i++)
  {
    const mrpt::poses::CPose2D rel = truth[i] - truth[0];
    odo.push_back(i >= from ? error + rel : rel);
  }
  return odo;
}
}  // namespace voxplore::test
