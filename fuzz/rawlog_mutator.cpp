/* voxplore fuzz harness: the mutator of fuzz_rawlog, half plain byte
 * mutation (libFuzzer's own, LLVMFuzzerMutate) and half structure-aware.
 *
 * Plain byte mutation finds, within seconds, inputs on which MRPT 2.5.8
 * crashes (fuzz/mrpt_crashes/, fuzz/README.md): a null dereference in
 * CActionRobotMovement2D::serializeFrom, length fields that allocate GBs
 * unchecked. The reader under test parses every object in a forked child
 * first, so those are errors now, and the target takes any bytes.
 *
 * Plain mutation rarely makes a well-formed MRPT payload, so the other half
 * keeps payloads well-formed and mutates what our reader (libs/common
 * forEachRawlogEntry) decides on: which objects come in which order (action
 * collections, sensory frames, bare observations, foreign classes), their
 * contents through MRPT's API (range images of any size 0..16 px, NaN/inf/huge
 * poses, ranges, units, timestamps, empty frames), truncation at any byte,
 * trailing garbage that MRPT rejects at the object header, and gzip or not.
 * It reads the input's objects with the same protected reader
 * (forEachRawlogObject): a raw-mutated input may crash MRPT too. */

#include <mrpt/io/CMemoryStream.h>
#include <mrpt/io/zip.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/serialization/CArchive.h>

#include <unistd.h>
#include <voxplore/common/rawlog_io.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

namespace
{
using Obj = mrpt::serialization::CSerializable::Ptr;
using Bytes = std::vector<std::uint8_t>;
using Rng = std::mt19937;

/// A deep copy of an MRPT object as `T`.
template <typename T>
typename T::Ptr deepCopy(const T& o)
{
  return std::dynamic_pointer_cast<T>(o.duplicateGetSmartPtr());
}

bool isGzip(const std::uint8_t* d, std::size_t n)
{
  return n >= 2 && d[0] == 0x1f && d[1] == 0x8b;
}

/// The leading objects of `data` (plain or gzip) that MRPT reads whole, by
/// the protected reader (a child process parses them first); stops at the
/// first fault.
std::vector<Obj> parseObjects(const std::uint8_t* data, std::size_t size, bool& gzip)
{
  gzip = isGzip(data, size);
  std::vector<Obj> objects;
  if (size == 0)
  {
    return objects;
  }
  namespace fs = std::filesystem;
  static const std::string path =
      ((fs::is_directory("/dev/shm") ? fs::path("/dev/shm") : fs::temp_directory_path()) /
       ("voxplore_fuzz_mutator_" + std::to_string(::getpid()) + ".rawlog"))
          .string();
  static const bool registered = (std::atexit([] { std::remove(path.c_str()); }), true);
  (void)registered;
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  voxplore::common::RawlogReadOptions opts;
  opts.object_memory_mb = 32;
  opts.object_timeout_ms = 1000;
  opts.fresh_child_when_threaded = false;  // libFuzzer's watchdog thread holds no lock the child needs
  try
  {
    voxplore::common::forEachRawlogObject(
        path,
        [&](const Obj& o, std::uint64_t)
        {
          if (!o)
          {
            return false;
          }
          objects.push_back(o);
          return true;
        },
        opts);
  }
  catch (const std::runtime_error&)
  {
  }
  return objects;
}

double pickDouble(Rng& rng)
{
  static const double kSpecial[] = {0.0,
                                    -0.0,
                                    1.0,
                                    -1.0,
                                    1e-300,
                                    1e300,
                                    -1e300,
                                    std::numeric_limits<double>::quiet_NaN(),
                                    std::numeric_limits<double>::infinity(),
                                    -std::numeric_limits<double>::infinity()};
  if (rng() % 2 == 0)
  {
    return kSpecial[rng() % (sizeof(kSpecial) / sizeof(kSpecial[0]))];
  }
  return std::uniform_real_distribution<double>(-50.0, 50.0)(rng);
}

float pickFloat(Rng& rng)
{
  const double d = pickDouble(rng);
  if (!(std::abs(d) <= std::numeric_limits<float>::max()))
  {
    return std::isnan(d) ? std::numeric_limits<float>::quiet_NaN()
                         : std::copysign(std::numeric_limits<float>::infinity(), d);
  }
  return static_cast<float>(d);
}

mrpt::Clock::time_point pickTime(Rng& rng)
{
  static const std::int64_t kSpecial[] = {0, 1, -1, std::numeric_limits<std::int64_t>::max(),
                                          std::numeric_limits<std::int64_t>::min()};
  const std::int64_t t =
      rng() % 2 == 0 ? kSpecial[rng() % 5] : static_cast<std::int64_t>(rng()) * 1000003;
  return mrpt::Clock::time_point(mrpt::Clock::duration(t));
}

void mutateScan(mrpt::obs::CObservation3DRangeScan& s, Rng& rng)
{
  switch (rng() % 6)
  {
    case 0:
    {
      const auto rows = static_cast<int>(rng() % 17);
      const auto cols = static_cast<int>(rng() % 17);
      s.rangeImage.resize(rows, cols);
      for (int r = 0; r < rows; ++r)
      {
        for (int c = 0; c < cols; ++c)
        {
          s.rangeImage(r, c) = static_cast<std::uint16_t>(rng());
        }
      }
      s.hasRangeImage = rng() % 4 != 0;
      break;
    }
    case 1:
      if (s.rangeImage.rows() > 0 && s.rangeImage.cols() > 0)
      {
        static const std::uint16_t kRanges[] = {0, 1, 0xFFFF, 7000};
        s.rangeImage(static_cast<int>(rng() % s.rangeImage.rows()),
                     static_cast<int>(rng() % s.rangeImage.cols())) = kRanges[rng() % 4];
      }
      break;
    case 2:
      s.rangeUnits = pickFloat(rng);
      break;
    case 3:
      s.maxRange = pickFloat(rng);
      break;
    case 4:
      s.sensorPose = mrpt::poses::CPose3D(pickDouble(rng), pickDouble(rng), pickDouble(rng),
                                          pickDouble(rng), pickDouble(rng), pickDouble(rng));
      break;
    default:
      s.timestamp = pickTime(rng);
      break;
  }
}

void mutateObservation(mrpt::obs::CObservation& o, Rng& rng)
{
  if (auto* scan = dynamic_cast<mrpt::obs::CObservation3DRangeScan*>(&o))
  {
    mutateScan(*scan, rng);
  }
  else if (auto* odo = dynamic_cast<mrpt::obs::CObservationOdometry*>(&o))
  {
    odo->odometry = mrpt::poses::CPose2D(pickDouble(rng), pickDouble(rng), pickDouble(rng));
  }
  else
  {
    o.timestamp = pickTime(rng);
  }
}

mrpt::obs::CObservation::Ptr newObservation(Rng& rng)
{
  switch (rng() % 3)
  {
    case 0:
      return mrpt::obs::CObservation2DRangeScan::Create();  // 2D laser: the wrong kind
    case 1:
    {
      auto scan = mrpt::obs::CObservation3DRangeScan::Create();
      scan->sensorLabel = "CAM0";
      mutateScan(*scan, rng);
      return scan;
    }
    default:
      return mrpt::obs::CObservationOdometry::Create();
  }
}

void mutateFrame(mrpt::obs::CSensoryFrame& sf, Rng& rng)
{
  const std::size_t n = sf.size();
  switch (rng() % 4)
  {
    case 0:
      if (n > 0)
      {
        sf.eraseByIndex(rng() % n);
      }
      break;
    case 1:
      sf.insert(newObservation(rng));
      break;
    case 2:
      if (n > 0)
      {
        sf.insert(deepCopy<mrpt::obs::CObservation>(*sf.getObservationByIndex(rng() % n)));
      }
      break;
    default:
      if (n > 0)
      {
        mutateObservation(*sf.getObservationByIndex(rng() % n), rng);
      }
      break;
  }
}

void mutateActions(mrpt::obs::CActionCollection& acts, Rng& rng)
{
  const std::size_t n = acts.size();
  if (n == 0)
  {
    return;  // a fresh CActionRobotMovement2D has no poseChange: MRPT cannot read it back
  }
  const std::size_t i = rng() % n;
  switch (rng() % 3)
  {
    case 0:
      acts.eraseByIndex(i);
      break;
    case 1:
      acts.insertPtr(deepCopy<mrpt::obs::CAction>(*acts.get(i)));
      break;
    default:
      if (auto* mv = dynamic_cast<mrpt::obs::CActionRobotMovement2D*>(acts.get(i).get()))
      {
        mv->rawOdometryIncrementReading =
            mrpt::poses::CPose2D(pickDouble(rng), pickDouble(rng), pickDouble(rng));
        mv->timestamp = pickTime(rng);
      }
      break;
  }
}

/// One structural change to the object sequence.
void mutateObjects(std::vector<Obj>& objs, Rng& rng)
{
  const std::size_t n = objs.size();
  const std::size_t i = n > 0 ? rng() % n : 0;
  switch (rng() % 8)
  {
    case 0:
      if (n > 0)
      {
        objs.erase(objs.begin() + static_cast<long>(i));
      }
      break;
    case 1:
      if (n > 0)
      {
        objs.insert(objs.begin() + static_cast<long>(i),
                    deepCopy<mrpt::serialization::CSerializable>(*objs[i]));
      }
      break;
    case 2:
      if (n > 1)
      {
        std::swap(objs[i], objs[rng() % n]);
      }
      break;
    case 3:
    {
      auto sf = mrpt::obs::CSensoryFrame::Create();
      sf->insert(newObservation(rng));
      objs.insert(objs.begin() + static_cast<long>(i), sf);
      break;
    }
    case 4:
    {
      Obj extra;
      switch (rng() % 3)
      {
        case 0:
          extra = mrpt::obs::CActionCollection::Create();
          break;
        case 1:
          extra = newObservation(rng);
          break;  // observation-only format
        default:
          extra = mrpt::poses::CPose2D::Create(1, 2, 3);
          break;  // a foreign class
      }
      objs.insert(objs.begin() + static_cast<long>(i), extra);
      break;
    }
    default:
      if (n == 0)
      {
        break;
      }
      if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(objs[i]))
      {
        mutateFrame(*sf, rng);
      }
      else if (auto acts = std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(objs[i]))
      {
        mutateActions(*acts, rng);
      }
      else if (auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservation>(objs[i]))
      {
        mutateObservation(*obs, rng);
      }
      break;
  }
}

Bytes serialize(const std::vector<Obj>& objs)
{
  mrpt::io::CMemoryStream ms;
  auto arch = mrpt::serialization::archiveFrom(ms);
  for (const auto& o : objs)
  {
    arch.WriteObject(o.get());
  }
  const auto* b = static_cast<const std::uint8_t*>(ms.getRawBufferData());
  return Bytes(b, b + ms.getTotalBytesCount());
}
}  // namespace

extern "C" std::size_t LLVMFuzzerMutate(std::uint8_t* data, std::size_t size, std::size_t max_size);

extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size,
                                               std::size_t max_size, unsigned int seed)
{
  Rng rng(seed);
  if (rng() % 2 == 0)
  {
    return LLVMFuzzerMutate(data, size, max_size);  // plain bytes: the reader takes any
  }
  bool gzip = false;
  Bytes out;
  try
  {
    std::vector<Obj> objs = parseObjects(data, size, gzip);
    const unsigned edits = 1 + rng() % 3;
    for (unsigned e = 0; e < edits; ++e)
    {
      mutateObjects(objs, rng);
    }
    out = serialize(objs);
  }
  catch (const std::exception&)
  {
    return size;  // MRPT refused to write what we built: keep the input
  }
  switch (rng() % 6)
  {
    case 0:
      if (!out.empty())
      {
        out.resize(rng() % out.size());  // truncated at any byte
      }
      break;
    case 1:
    {
      // Trailing garbage: any bytes (a header byte >= 0x80 names a class
      // whose payload MRPT then parses; the reader's child takes the risk).
      out.push_back(static_cast<std::uint8_t>(rng()));
      for (unsigned k = rng() % 8; k > 0; --k)
      {
        out.push_back(static_cast<std::uint8_t>(rng()));
      }
      break;
    }
    case 2:
      gzip = !gzip;
      break;
    default:
      break;
  }
  if (gzip)
  {
    Bytes gz;
    if (mrpt::io::zip::compress_gz_data_block(out, gz, 1))
    {
      out.swap(gz);
    }
    if (!out.empty() && rng() % 4 == 0)
    {
      out.resize(rng() % out.size());  // a truncated gzip stream
    }
  }
  if (out.size() > max_size)
  {
    return size;
  }
  if (!out.empty())
  {
    std::memcpy(data, out.data(), out.size());
  }
  return out.size();
}
