#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/serialization/CSerializable.h>
#include <voxplore/common/rawlog_io.h>

#include <filesystem>
#include <stdexcept>

namespace voxplore::common
{
namespace
{
/// Reads all or nothing. MRPT's CArchive accepts a short read inside a field
/// (ReadBuffer throws only when zero bytes come): a rawlog truncated inside a
/// uint32 count leaves that count's last bytes unset, and the garbage count
/// then allocates gigabytes or loops for minutes (found by fuzz/fuzz_rawlog).
/// Reporting a short read as zero bytes makes CArchive throw at once.
/// consumed() tells a clean end of file (CExceptionEOF at an object boundary)
/// from a file cut at the boundary of an object nested in another.
class AllOrNothingInput : public mrpt::io::CStream
{
 public:
  explicit AllOrNothingInput(mrpt::io::CStream& in) : in_(in) {}

  size_t Read(void* buffer, size_t count) override
  {
    auto* p = static_cast<unsigned char*>(buffer);
    size_t got = 0;
    while (got < count)
    {
      const size_t n = in_.Read(p + got, count - got);
      if (n == 0) break;
      got += n;
    }
    consumed_ += got;
    return got == count ? count : 0;
  }
  /// Bytes taken from the underlying stream so far.
  uint64_t consumed() const { return consumed_; }
  size_t Write(const void*, size_t) override { return 0; }
  uint64_t Seek(int64_t offset, TSeekOrigin origin) override { return in_.Seek(offset, origin); }
  uint64_t getTotalBytesCount() const override { return in_.getTotalBytesCount(); }
  uint64_t getPosition() const override { return in_.getPosition(); }

 private:
  mrpt::io::CStream& in_;
  uint64_t consumed_ = 0;
};
}  // namespace

RawlogWriter::RawlogWriter(const std::string& path) : path_(path)
{
  out_.open(path, std::ios::binary | std::ios::trunc);
  if (!out_)
    throw std::runtime_error("cannot create rawlog file '" + path + "'");
}

RawlogWriter::~RawlogWriter() = default;

void RawlogWriter::write(
    const mrpt::obs::CActionCollection& actions, const mrpt::obs::CSensoryFrame& sf)
{
  mrpt::io::CMemoryStream buf;
  auto arch = mrpt::serialization::archiveFrom(buf);
  arch << actions << sf;
  // Written and flushed per pair: every completed stop survives a crash.
  out_.write(static_cast<const char*>(buf.getRawBufferData()),
             static_cast<std::streamsize>(buf.getTotalBytesCount()));
  out_.flush();
  if (!out_) throw std::runtime_error("write failed: '" + path_ + "' (disk full?)");
  entries_++;
}

std::size_t forEachRawlogEntry(
    const std::string& path, const std::function<bool(const RawlogEntry&)>& visit)
{
  namespace fs = std::filesystem;
  if (!fs::is_regular_file(path))
    throw std::runtime_error("rawlog file not found: '" + path + "'");
  if (fs::file_size(path) == 0) throw std::runtime_error("rawlog file is empty: '" + path + "'");
  mrpt::io::CFileGZInputStream in;
  if (!in.open(path)) throw std::runtime_error("cannot open rawlog file '" + path + "'");
  AllOrNothingInput exact(in);
  auto arch = mrpt::serialization::archiveFrom(exact);

  std::size_t n = 0;
  mrpt::obs::CActionCollection::Ptr pending_actions;
  auto fail = [&](const std::string& why) {
    throw std::runtime_error(path + ": corrupt or truncated rawlog at entry " + std::to_string(n) +
                             " (" + std::to_string(n) + " entries read before): " + why);
  };
  for (;;)
  {
    mrpt::serialization::CSerializable::Ptr obj;
    const uint64_t consumed_before = exact.consumed();
    try
    {
      obj = arch.ReadObject();
    }
    catch (const mrpt::serialization::CExceptionEOF&)
    {
      // MRPT throws EOF also for a nested object's missing header: a file cut
      // there is truncated, not complete (found by tests on every cut length).
      if (exact.consumed() != consumed_before) fail("the file ends inside an object");
      if (pending_actions) fail("ends after an action collection without its sensory frame");
      break;
    }
    catch (const std::exception& e)
    {
      fail(e.what());
    }
    RawlogEntry entry;
    entry.index = n;
    if (auto acts = std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(obj))
    {
      if (pending_actions) fail("two action collections in a row");
      pending_actions = acts;
      continue;
    }
    if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(obj))
    {
      entry.actions = pending_actions;
      entry.observations = sf;
      pending_actions.reset();
    }
    else if (auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj))
    {
      if (pending_actions) fail("an observation follows an action collection");
      entry.observations = mrpt::obs::CSensoryFrame::Create();
      entry.observations->insert(obs);
    }
    else
    {
      fail(std::string("unexpected object of class ") +
           (obj ? obj->GetRuntimeClass()->className : "null"));
    }
    n++;
    if (!visit(entry)) break;
  }
  if (n == 0) throw std::runtime_error(path + ": the rawlog holds no entries");
  return n;
}

}  // namespace voxplore::common
