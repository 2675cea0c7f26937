// Ray casting with Embree 3: a BVH over the world triangles, queried on the
// caller's thread. Embree rather than our own kernel: it is the fastest
// well-kept CPU ray tracer in Debian (about 2 ms per 24,576-ray scan).
#include <embree3/rtcore.h>
#include <voxplore/sim/RayCaster.h>

#include <stdexcept>
#include <string>

namespace voxplore::sim
{
struct RayCaster::Impl
{
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~Impl()
  {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace
{
void throwOnError(RTCDevice device, const char* what)
{
  const RTCError err = rtcGetDeviceError(device);
  if (err != RTC_ERROR_NONE)
    throw std::runtime_error(std::string("Embree error ") + std::to_string(int(err)) + " in " + what);
}

inline void initRay(RTCRayHit& rh, const Eigen::Vector3f& o, const Eigen::Vector3f& d, float tn, float tf)
{
  rh.ray.org_x = o.x();
  rh.ray.org_y = o.y();
  rh.ray.org_z = o.z();
  rh.ray.dir_x = d.x();
  rh.ray.dir_y = d.y();
  rh.ray.dir_z = d.z();
  rh.ray.tnear = tn;
  rh.ray.tfar = tf;
  rh.ray.time = 0.0f;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}
}  // namespace

RayCaster::RayCaster(const TriangleMesh& mesh) : impl_(std::make_unique<Impl>())
{
  // One build thread: the BVH is built once per world; keeps runs reproducible.
  // max_isa: Embree picks its kernels by the CPU at run time, and its AVX-512
  // and AVX2 kernels do not return the same hit distances to the last bit, so
  // a run took another course on another machine (BENCHMARKS.md, "Forty-third
  // session"). SSE4.2, which every x86-64 machine in use has, on all of them.
  impl_->device = rtcNewDevice("threads=1,max_isa=sse4.2");
  if (!impl_->device) throw std::runtime_error("Embree: rtcNewDevice failed");
  impl_->scene = rtcNewScene(impl_->device);
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);

  if (!mesh.empty())
  {
    RTCGeometry geom = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
        mesh.vertices.size()));
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
        mesh.triangles.size()));
    throwOnError(impl_->device, "buffer allocation");
    for (std::size_t i = 0; i < mesh.vertices.size(); i++)
      for (int k = 0; k < 3; k++) vb[3 * i + k] = mesh.vertices[i][k];
    for (std::size_t i = 0; i < mesh.triangles.size(); i++)
      for (int k = 0; k < 3; k++) ib[3 * i + k] = static_cast<unsigned>(mesh.triangles[i][k]);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(impl_->scene, geom);
    rtcReleaseGeometry(geom);
  }
  rtcCommitScene(impl_->scene);
  throwOnError(impl_->device, "scene build");
}

RayCaster::~RayCaster() = default;

float RayCaster::cast(
    const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, float t_near, float t_far) const
{
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh;
  initRay(rh, origin, dir, t_near, t_far);
  rtcIntersect1(impl_->scene, &ctx, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::numeric_limits<float>::infinity();
  return rh.ray.tfar;
}

int RayCaster::nativePacketWidth() const
{
  if (rtcGetDeviceProperty(impl_->device, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED)) return 16;
  if (rtcGetDeviceProperty(impl_->device, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED)) return 8;
  if (rtcGetDeviceProperty(impl_->device, RTC_DEVICE_PROPERTY_NATIVE_RAY4_SUPPORTED)) return 4;
  return 1;
}

void RayCaster::castFan(
    const Eigen::Vector3f& origin, const Eigen::Vector3f* dirs, std::size_t n, float t_near,
    float t_far, float* t_out) const
{
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;  // rays of one camera share an origin
  constexpr std::size_t kPacket = 16;
  alignas(64) RTCRayHit16 rh;
  alignas(64) int valid[kPacket];
  for (std::size_t base = 0; base < n; base += kPacket)
  {
    const std::size_t m = std::min(kPacket, n - base);
    for (std::size_t i = 0; i < kPacket; i++)
    {
      const bool on = i < m;
      valid[i] = on ? -1 : 0;
      const Eigen::Vector3f& d = dirs[base + (on ? i : 0)];
      rh.ray.org_x[i] = origin.x();
      rh.ray.org_y[i] = origin.y();
      rh.ray.org_z[i] = origin.z();
      rh.ray.dir_x[i] = d.x();
      rh.ray.dir_y[i] = d.y();
      rh.ray.dir_z[i] = d.z();
      rh.ray.tnear[i] = t_near;
      rh.ray.tfar[i] = t_far;
      rh.ray.time[i] = 0.0f;
      rh.ray.mask[i] = 0xFFFFFFFFu;
      rh.ray.id[i] = 0;
      rh.ray.flags[i] = 0;
      rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect16(valid, impl_->scene, &ctx, &rh);
    for (std::size_t i = 0; i < m; i++)
      t_out[base + i] = rh.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID
                            ? std::numeric_limits<float>::infinity()
                            : rh.ray.tfar[i];
  }
}

}  // namespace voxplore::sim
