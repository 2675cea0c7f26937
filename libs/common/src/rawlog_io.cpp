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
  auto arch = mrpt::serialization::archiveFrom(in);

  std::size_t n = 0;
  mrpt::obs::CActionCollection::Ptr pending_actions;
  auto fail = [&](const std::string& why) {
    throw std::runtime_error(path + ": corrupt or truncated rawlog at entry " + std::to_string(n) +
                             " (" + std::to_string(n) + " entries read before): " + why);
  };
  for (;;)
  {
    mrpt::serialization::CSerializable::Ptr obj;
    try
    {
      obj = arch.ReadObject();
    }
    catch (const mrpt::serialization::CExceptionEOF&)
    {
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
