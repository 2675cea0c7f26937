/* voxplore — depth-camera mounting poses on the robot and their ini keys,
 * shared by the simulator's camera rig and the planner's virtual cameras. */
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/poses/CPose3D.h>

#include <string>
#include <vector>

namespace voxplore::common
{
/// @brief The thesis' ring of 8 cameras (thesis 4.1.2, DESIGN.md): yaws 0,
///        +-40, +-90, +-140, 180 deg, each where its viewing direction leaves
///        the length x width footprint rectangle, at `height_m`, pitched down
///        by vfov/2 so the top image row is horizontal. MRPT camera frame:
///        +X depth, +Y left, +Z up; positive pitch looks down.
std::vector<mrpt::poses::CPose3D> cameraRing(
    double length_m, double width_m, double height_m, double vfov_rad);

/// @brief Does a half turn of the robot (yaw + pi) map the set of camera
///        mounts onto itself (each mount onto one within 1 mm and 0.1 deg)?
///        Then a view and the view half a turn round it see the same.
bool mountsSymmetricUnderHalfTurn(const std::vector<mrpt::poses::CPose3D>& mounts);

/// @brief ini key of camera i's pose: "cam<i>_pose".
std::string cameraPoseKey(int i);

/// @brief Reads "camN_pose = x y z yaw_deg pitch_deg roll_deg" for N <
///        num_cameras into `mounts` when any is given (then all must be);
///        with none given, `mounts` is kept and must hold num_cameras poses.
/// @throws std::runtime_error naming the file, section and key otherwise.
void loadCameraMounts(
    const mrpt::config::CConfigFileBase& c, const std::string& section, int num_cameras,
    std::vector<mrpt::poses::CPose3D>& mounts);

/// @brief Writes every mount as camN_pose (degrees).
void saveCameraMounts(
    mrpt::config::CConfigFileBase& c, const std::string& section,
    const std::vector<mrpt::poses::CPose3D>& mounts);

}  // namespace voxplore::common
