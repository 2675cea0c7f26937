/* voxplore — ray casting against a triangle mesh (Embree 3 BVH). */
#pragma once

#include <voxplore/sim/TriangleMesh.h>

#include <Eigen/Core>
#include <limits>
#include <memory>

namespace voxplore::sim
{
/// @brief Casts rays against a static triangle mesh. Built once (Embree BVH);
///        queries are const and thread-safe, and run on the calling thread.
class RayCaster
{
 public:
  explicit RayCaster(const TriangleMesh& mesh);
  ~RayCaster();
  RayCaster(const RayCaster&) = delete;
  RayCaster& operator=(const RayCaster&) = delete;

  /// @brief Distance along `dir` (need not be unit: the result is in units of
  ///        |dir|) to the first triangle hit in [t_near, t_far].
  /// @return +infinity when nothing is hit in that interval.
  float cast(
      const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, float t_near = 0.0f,
      float t_far = std::numeric_limits<float>::infinity()) const;

  /// @brief Casts `n` rays sharing one origin; `t_out[i]` as for cast().
  ///        Uses Embree's 16-wide packets.
  void castFan(
      const Eigen::Vector3f& origin, const Eigen::Vector3f* dirs, std::size_t n, float t_near,
      float t_far, float* t_out) const;

  /// @brief The widest ray packet Embree's kernels in force trace natively
  ///        (4 for the SSE4.2 kernels the caster is held to, 8 for AVX and
  ///        AVX2, 16 for AVX-512): a machine-independent run needs 4.
  int nativePacketWidth() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace voxplore::sim
