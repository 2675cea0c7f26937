/* voxplore — SlamIcp (thesis 4.4): pose prediction, cloud per stop, planar ICP
 * against the metaview, point reduction, OctoMap integration. A metric map
 * builder of our own in the spirit of MRPT's CMetricMapBuilder (process an
 * observation, current pose, current map, save); CMetricMapBuilderICP
 * diverges on our data (one ICP per narrow camera, DESIGN.md). */
#pragma once

#include <mrpt/core/Clock.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <voxplore/mapping/LoopClosure.h>
#include <voxplore/mapping/Metaview.h>
#include <voxplore/mapping/OctoMapLayer.h>
#include <voxplore/mapping/PlanarIcp.h>
#include <voxplore/mapping/robot_cloud.h>

#include <optional>
#include <set>
#include <string>
#include <vector>

namespace voxplore::mapping
{
/// @brief All SlamIcp settings: sections [cloud], [metaview], [icp], [octomap], [loop_closure].
struct SlamIcpParams
{
  CloudParams cloud;
  MetaviewParams metaview;
  IcpParams icp;
  OctoMapParams octomap;
  LoopClosureParams loop_closure;

  /// @brief Loads the four sections (unknown keys / bad values throw naming file and key).
  void load(const mrpt::config::CConfigFileBase& cfg);
  void save(mrpt::config::CConfigFileBase& cfg) const;
  /// @brief The section names this struct reads.
  static std::vector<std::string> sections()
  {
    return {"cloud", "metaview", "icp", "octomap", "loop_closure"};
  }
};

/// @brief What happened at one stop (also one row of stops.csv).
struct StopReport
{
  std::size_t index = 0;
  mrpt::Clock::time_point timestamp;
  mrpt::poses::CPose2D odometry;    ///< raw odometry reading
  mrpt::poses::CPose2D predicted;   ///< eq. 4.2 prediction, map frame
  mrpt::poses::CPose2D pose;        ///< final T_map_robot
  /// The estimate when the robot left the stop (this stop's own loop
  /// closure included; later confirmations and relaxations not):
  /// trajectory_online.tum. Its error against the final pose's says what
  /// the pose graph corrected afterwards.
  mrpt::poses::CPose2D online_pose;
  IcpResult icp;
  /// The pose is odometry only although ICP is enabled and this is not the
  /// first stop: ICP rejected or impossible (no usable camera, too few
  /// points, empty metaview). See icp.reason.
  bool flagged = false;
  /// The stop entered the metaview, the octree and the simplemap. A flagged
  /// stop does not, unless the metaview is still empty (then its odometry
  /// pose starts the map: nothing can be corrupted yet).
  bool integrated = false;
  bool relocalized = false;         ///< ICP rejected the prediction, relocalizePlanar() found the pose
  /// Registered from the prediction carrying the previous stop's refused
  /// correction, and agreeing with it ([icp] confirm_large_corrections): the
  /// previous stop's pose was corrected too.
  bool confirmed_correction = false;
  /// ICP converged and passed its checks, but its correction was too large
  /// for its goodness ([icp] hold_sigmas, hold_min_m, hold_sure_goodness):
  /// the stop is flagged, at its prediction, until the next stop confirms it.
  bool held = false;
  /// The registration was refused or held, and the odometry prediction fit
  /// the cloud at least as well: the stop keeps the prediction and enters the
  /// map ([icp] keep_fitting_prediction). Its std still counts as unregistered.
  bool odometry_kept = false;
  std::size_t cameras_used = 0;     ///< depth images that passed checkDepthScan()
  std::vector<CameraIssue> camera_issues;  ///< skipped, cleaned or missing cameras
  std::vector<std::string> warnings;       ///< one line per issue, for the user
  std::size_t cloud_points = 0;     ///< |Q| after the floor cut
  std::size_t invalid_pixels = 0;
  std::size_t deskewed_cameras = 0;  ///< depth images moved to their exposure's pose ([cloud] deskew)
  std::size_t metaview_added = 0;
  std::size_t metaview_size = 0;
  InsertStats octomap;
  /// Loop closure at this stop (keyframes only). When `loop.closed`, every
  /// earlier report's pose was corrected and the maps may have been rebuilt.
  LoopEvent loop;
  /// After a closure, keyframes re-inserted into the OctoMap being rebuilt
  /// at this stop, and how many are left after it ([loop_closure]
  /// octomap_rebuild_per_stop).
  std::size_t octomap_rebuilt_keyframes = 0, octomap_rebuild_left = 0;
  double t_cloud_ms = 0, t_icp_ms = 0, t_metaview_ms = 0, t_octomap_ms = 0, t_total_ms = 0;
  double t_octomap_rebuild_ms = 0;  ///< re-inserting those keyframes [ms]
};

/// @brief The SlamIcp process. Not thread-safe; one instance per run.
class SlamIcp
{
 public:
  explicit SlamIcp(const SlamIcpParams& params);

  /// @brief Processes one stop: its depth images and odometry reading.
  ///        The first stop defines the map frame (pose = origin whatever the
  ///        odometry reads, thesis 4.4.1) and frees the start box.
  ///        Faulty sensor data never throws and never reaches the maps:
  ///        depth images failing checkDepthScan() are skipped (a warning
  ///        naming the camera and the reason), cameras seen at earlier stops
  ///        but missing here are reported, a non-finite odometry reading
  ///        counts as no motion, and a stop without any usable depth image
  ///        keeps the odometry prediction (flagged, not integrated).
  StopReport processStop(
      const mrpt::obs::CSensoryFrame& sf, const mrpt::poses::CPose2D& odometry,
      mrpt::Clock::time_point timestamp);

  /// @brief The odometry reading of a rawlog entry: a CObservationOdometry in
  ///        `sf`, else the increment of a CActionRobotMovement2D in `actions`
  ///        accumulated onto the previous reading. Empty when neither exists.
  std::optional<mrpt::poses::CPose2D> odometryOf(
      const mrpt::obs::CActionCollection* actions, const mrpt::obs::CSensoryFrame& sf);

  mrpt::poses::CPose2D currentPose() const { return pose_; }
  std::size_t numStops() const { return reports_.size(); }
  const Metaview& metaview() const { return metaview_; }
  const OctoMapLayer& octomap() const { return octomap_; }
  OctoMapLayer& octomap() { return octomap_; }
  const mrpt::maps::CSimpleMap& simplemap() const { return simplemap_; }
  const std::vector<StopReport>& reports() const { return reports_; }
  const SlamIcpParams& params() const { return params_; }
  /// @brief The keyframes and pose graph (empty when [loop_closure] enabled = false).
  const LoopCloser& loopCloser() const { return loop_; }
  /// @brief Loops closed (confirmed and relaxed) so far, and the largest graph shift [m].
  std::size_t loopClosures() const { return loop_closures_; }
  double maxGraphShift() const { return max_graph_shift_m_; }

  /// @brief Moves the metaview to the keyframes' current poses (after a
  ///        relaxation) and rebuilds the OctoMap from them: at once when
  ///        `octomap_keyframes` is 0, else only that many keyframes now and
  ///        the rest over the next stops ([loop_closure]
  ///        octomap_rebuild_per_stop). Returns its time [ms].
  double rebuildMaps(std::size_t octomap_keyframes = 0);
  /// @brief Keyframes still to be re-inserted into the OctoMap being rebuilt
  ///        (0: octomap() is the map at the corrected poses).
  std::size_t octomapRebuildPending() const;
  /// @brief Completes a rebuild in progress (the outputs and the evaluation
  ///        want the corrected map); returns its time [ms].
  double finishMapRebuild();

  /// @brief Writes map.bt, map.simplemap, metaview.ply, trajectory_est.tum
  ///        and stops.csv into `dir` (which must exist), after completing an
  ///        OctoMap rebuild in progress.
  /// @throws std::runtime_error naming the file that could not be written.
  void saveOutputs(const std::string& dir);

 private:
  /// Fills the camera checks of `rep` (usable, skipped, missing cameras).
  void checkCameras(const mrpt::obs::CSensoryFrame& sf, StopReport& rep, UsableScans& usable);
  /// Step 3: ICP (and relocalisation) or the prediction; sets pose, icp, flagged.
  void registerStop(StopReport& rep, const RobotCloud& cloud, bool has_depth);
  /// The odometry's xy std [m] of the prediction `predicted` from the last
  /// stop ICP registered (not flagged), summed step by step (odometryStdXy).
  double odometryStdSinceRegistered(const mrpt::poses::CPose2D& predicted) const;
  /// After a rejected registration: when the previous stop's registration
  /// was refused only for its size, try this stop from the prediction
  /// carrying that correction; true when it agrees (rep.icp replaced).
  struct LargeCorrection;
  bool confirmLargeCorrection(StopReport& rep, const RobotCloud& cloud, const LargeCorrection& lc);
  /// Occupied voxels of the OctoMap inside the robot's body at `pose` ([icp] body_*).
  std::size_t occupiedUnderBody(const mrpt::poses::CPose2D& pose) const;
  /// More than [icp] body_max_voxels of them.
  bool bodyBlocked(const mrpt::poses::CPose2D& pose) const;
  /// An accepted `r` whose body holds more than body_max_voxels occupied
  /// voxels is refused (pose back to `predicted`, the reason says why); true then.
  bool refuseIfBodyBlocked(IcpResult& r, const mrpt::poses::CPose2D& predicted) const;
  /// After a rejected registration: relocalizePlanar() round the prediction
  /// among poses whose body is clear, from body_relocalize_min_goodness when
  /// the registration was refused for the body; replaces rep.icp.
  void relocalize(StopReport& rep, const RobotCloud& cloud, bool body_refused);
  /// Turns an accepted registration into a held one ([icp] hold_sigmas):
  /// std_since_m is the prediction's odometry std since the last registered stop.
  void holdIfUnsure(StopReport& rep, double std_since_m);
  /// A refused or held registration that fits the cloud no better than the
  /// odometry prediction gives way to it ([icp] keep_fitting_prediction).
  void keepFittingPrediction(StopReport& rep, const RobotCloud& cloud, const IcpResult& first_try,
                             double std_since_m);
  /// Steps 4 and 5 and the keyframe, for a stop that is integrated.
  void integrateStop(StopReport& rep, const RobotCloud& cloud,
                     const std::vector<mrpt::obs::CObservation3DRangeScan::Ptr>& scans,
                     const mrpt::obs::CSensoryFrame& sf);
  /// Keyframe, loop detection and, after a closure, the corrected poses and maps.
  void closeLoops(StopReport& rep, const RobotCloud& cloud);
  /// Copies the relaxed keyframe poses into the reports (stops between
  /// keyframes keep their offset to the keyframe before them) and the simplemap.
  void applyCorrection();
  /// Re-inserts up to `n` more keyframes into the OctoMap being rebuilt and
  /// swaps it in when it has caught up; returns how many were inserted.
  std::size_t advanceOctomapRebuild(std::size_t n);

  SlamIcpParams params_;
  Metaview metaview_;
  OctoMapLayer octomap_;
  mrpt::maps::CSimpleMap simplemap_;
  std::vector<StopReport> reports_;
  mrpt::poses::CPose2D pose_;
  std::optional<mrpt::poses::CPose2D> last_odometry_;
  std::optional<mrpt::poses::CPose2D> action_odometry_;  ///< accumulated action increments
  std::set<std::string> known_cameras_;  ///< labels of every depth camera seen so far
  LoopCloser loop_;
  /// The previous stop's registration, refused only for its size ([icp]
  /// confirm_large_corrections): its stop and ICP pose.
  struct LargeCorrection
  {
    std::size_t stop = 0;
    mrpt::poses::CPose2D icp_pose, predicted;
    double goodness = 0;
  };
  std::optional<LargeCorrection> large_correction_;
  double travel_m_ = 0;  ///< distance travelled along the estimate
  std::size_t loop_closures_ = 0;
  double max_graph_shift_m_ = 0;
  /// The OctoMap being rebuilt after a closure, and the next keyframe it takes.
  std::optional<OctoMapLayer> octomap_rebuild_;
  std::size_t octomap_rebuild_next_ = 0;
};

/// @brief Writes the per-stop CSV (header + one row per report).
void writeStopsCsv(const std::vector<StopReport>& reports, const std::string& path);

}  // namespace voxplore::mapping
