/* voxplore — one planning step's inputs written to disk and read back, so
 * that a step of a run can be planned again outside it (voxplore-plan). */
#pragma once

#include <mrpt/poses/CPose2D.h>
#include <voxplore/exploration/looks.h>
#include <voxplore/exploration/stages.h>

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace octomap
{
class OcTree;
}

namespace voxplore::exploration
{
/// @brief Everything plan() takes besides V and the parameters.
struct PlanInputs
{
  mrpt::poses::CPose2D robot;                 ///< the pose estimate planned from (map frame)
  uint64_t step = 0;                          ///< the planning step (seeds the sampler)
  std::vector<Eigen::Vector2d> blacklist;     ///< targets given up (map frame) [m]
  std::vector<Eigen::Vector2d> sensed_obstacles;  ///< points the driver sensed in the way [m]
  /// Cells of the map's low obstacles (OctoMapLayer::lowObstacles()), the
  /// planner takes them with the sensed points [m].
  std::vector<Eigen::Vector2d> low_obstacles;
  std::vector<Eigen::Vector2d> approach;      ///< frontiers to approach (nbv) [m]
  SweptPath swept;                            ///< poses the robot's centre swept [m, m, rad]
  /// The exploration region in force (ProjectionParams::region; set from the
  /// world after params.ini is written) [m]; empty: none.
  std::vector<Eigen::Vector2d> region;
  /// The unknown cells looked at so far and the stops not judged yet (plan()'s
  /// `looks`); null: none.
  std::shared_ptr<const FrontierLooks> looks;
};

/// @brief Writes `path` (text: one "robot x y yaw" line, "step N", then one
///        line per point: "bl x y", "so x y", "lo x y", "ap x y", "sw x y yaw", "rg x y",
///        and the looks: "lk kx ky n x y" per record, "ls x y yaw" per stop not judged; map
///        frame, metres and radians, full precision) and `path`.ot (V as
///        OctoMap's full .ot, log-odds kept: map.bt is thresholded and does
///        not plan the same).
/// @throws std::runtime_error naming the file when it cannot be written.
void writePlanInputs(const std::string& path, const PlanInputs& in, const octomap::OcTree& V);

/// @brief Reads what writePlanInputs wrote.
/// @param V_out the map read from `path`.ot
/// @throws std::runtime_error naming the file (and line) on a missing file,
///         an unknown tag, a bad number, or a map that is not an OcTree.
PlanInputs readPlanInputs(const std::string& path, std::unique_ptr<octomap::OcTree>& V_out);

}  // namespace voxplore::exploration
