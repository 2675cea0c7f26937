/* voxplore fuzz harness: a structure-aware mutator for fuzz_rawlog.
 *
 * Why not plain byte mutation: MRPT 2.5.8 deserialisation is not safe on
 * corrupt bytes, and those faults are MRPT's, out of our reach (reproducers
 * in fuzz/mrpt_crashes/, see fuzz/README.md):
 *  - a nested object of the wrong class (a CPose2D where CActionRobotMovement2D
 *    expects a CPosePDF) is a null-pointer dereference (SIGSEGV) in
 *    CActionRobotMovement2D::serializeFrom;
 *  - length fields are trusted: operator>>(CArchive&, std::string&) and
 *    CMatrixDynamic::realloc (range images) allocate what a corrupt uint32 says
 *    (GBs, zero-filled) before reading, and mrpt::aligned_allocator_cpp11 does
 *    not check for a failed allocation.
 * So this mutator keeps MRPT's object payloads well-formed and mutates what
 * our reader (libs/common forEachRawlogEntry) decides on: which objects come
 * in which order (action collections, sensory frames, bare observations,
 * foreign classes), their contents through MRPT's API (range images of any
 * size 0..16 px, NaN/inf/huge poses, ranges, units, timestamps, empty frames),
 * truncation at any byte, trailing garbage that MRPT rejects at the object
 * header, and gzip or not. */

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

#include <cstdint>
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

/// A byte buffer MRPT reads all or nothing, like forEachRawlogEntry's stream:
/// CArchive accepts a short read inside a field, and a seed cut inside a
/// uint32 count would otherwise give a garbage count (GBs) here.
class ExactBuffer : public mrpt::io::CStream
{
 public:
  explicit ExactBuffer(const Bytes& b) : b_(b) {}
  std::size_t Read(void* out, std::size_t n) override
  {
    if (n > b_.size() - pos_)
    {
      pos_ = b_.size();
      return 0;
    }
    std::memcpy(out, b_.data() + pos_, n);
    pos_ += n;
    return n;
  }
  std::size_t Write(const void*, std::size_t) override { return 0; }
  std::uint64_t Seek(std::int64_t, TSeekOrigin) override { return pos_; }
  std::uint64_t getTotalBytesCount() const override { return b_.size(); }
  std::uint64_t getPosition() const override { return pos_; }

 private:
  const Bytes& b_;
  std::size_t pos_ = 0;
};

/// The leading objects MRPT reads from `data` (plain or gzip); stops at the
/// first fault. Corpus inputs come from the seeds or this mutator, so their
/// payloads are well-formed up to a truncation or a rejected header.
std::vector<Obj> parseObjects(const std::uint8_t* data, std::size_t size, bool& gzip)
{
  Bytes raw(data, data + size);
  gzip = isGzip(data, size);
  if (gzip)
  {
    Bytes out;
    mrpt::io::zip::decompress_gz_data_block(raw, out);
    raw.swap(out);
  }
  std::vector<Obj> objects;
  if (raw.empty())
  {
    return objects;
  }
  ExactBuffer in(raw);
  auto arch = mrpt::serialization::archiveFrom(in);
  for (;;)
  {
    try
    {
      Obj o = arch.ReadObject();
      if (!o)
      {
        break;
      }
      objects.push_back(std::move(o));
    }
    catch (...)
    {
      break;
    }
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

extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size,
                                               std::size_t max_size, unsigned int seed)
{
  Rng rng(seed);
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
      // Trailing garbage MRPT rejects at the header byte (< 0x80: not a class
      // name length), so no corrupt payload reaches MRPT.
      out.push_back(static_cast<std::uint8_t>(rng() % 0x80));
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
