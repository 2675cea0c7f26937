#include <mrpt/io/CMemoryStream.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/serialization/CSerializable.h>
#include <voxplore/common/rawlog_io.h>

#include "rawlog_objects.h"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

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

std::string summaryLineOf(const std::string& text)
{
  // MRPT: "==== MRPT exception ====\nMessage:  WHAT\nOriginal exception:\n==== MRPT
  // exception ====\nMessage:  WHY\nLocation: ...\nCall stack backtrace: ...".
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);)
  {
    const auto a = l.find_first_not_of(" \t\r");
    if (a != std::string::npos) lines.push_back(l.substr(a, l.find_last_not_of(" \t\r") - a + 1));
  }
  std::string out;
  const std::string kMessage = "Message:";
  for (const auto& l : lines)
  {
    if (l.compare(0, kMessage.size(), kMessage) != 0) continue;
    const auto m = l.find_first_not_of(' ', kMessage.size());
    if (m != std::string::npos) out += (out.empty() ? "" : ": ") + l.substr(m);
  }
  if (out.empty()) out = lines.empty() ? std::string("(no message)") : lines.front();
  constexpr std::size_t kMax = 300;
  return out.size() > kMax ? out.substr(0, kMax) + "..." : out;
}

namespace
{
/// Checks the file and tells whether it is gzip-compressed.
bool checkRawlogFile(const std::string& path)
{
  namespace fs = std::filesystem;
  if (!fs::is_regular_file(path))
    throw std::runtime_error("rawlog file not found: '" + path + "'");
  if (fs::file_size(path) == 0) throw std::runtime_error("rawlog file is empty: '" + path + "'");
  std::ifstream f(path, std::ios::binary);
  char magic[2] = {0, 0};
  return f.read(magic, 2) && magic[0] == '\x1f' && magic[1] == '\x8b';
}

[[noreturn]] void throwAt(const std::string& path, bool gzip, const char* what, std::size_t index,
                          std::uint64_t offset, const std::string& why, const std::string& details)
{
  throw RawlogError(path + ": " + what + " " + std::to_string(index) + " (byte offset " +
                        std::to_string(offset) + (gzip ? " of the decompressed stream" : "") +
                        "): " + why,
                    details, index, offset);
}
}  // namespace

std::size_t forEachRawlogObject(
    const std::string& path,
    const std::function<bool(const mrpt::serialization::CSerializable::Ptr&, std::uint64_t)>& visit,
    const RawlogReadOptions& opts)
{
  const bool gzip = checkRawlogFile(path);
  detail::ObjectReader reader(path, opts);
  for (std::size_t n = 0;; n++)
  {
    const auto r = reader.next();
    if (r.kind == detail::ObjectRead::Kind::Failed)
      throwAt(path, gzip, "object", n, r.begin, r.reason, r.details);
    if (r.kind == detail::ObjectRead::Kind::End) return n;
    if (!visit(r.object, r.begin)) return n + 1;
  }
}

std::size_t forEachRawlogEntry(const std::string& path,
                               const std::function<bool(const RawlogEntry&)>& visit,
                               const RawlogReadOptions& opts)
{
  const bool gzip = checkRawlogFile(path);
  detail::ObjectReader reader(path, opts);

  std::size_t n = 0;
  mrpt::obs::CActionCollection::Ptr pending_actions;
  auto fail = [&](std::uint64_t offset, const std::string& why, const std::string& details = {}) {
    throwAt(path, gzip, "entry", n, offset, why, details);
  };
  for (;;)
  {
    const auto r = reader.next();
    if (r.kind == detail::ObjectRead::Kind::Failed) fail(r.begin, r.reason, r.details);
    if (r.kind == detail::ObjectRead::Kind::End)
    {
      if (pending_actions)
        fail(r.begin, "the file ends after an action collection without its sensory frame");
      break;
    }
    const auto& obj = r.object;
    RawlogEntry entry;
    entry.index = n;
    if (auto acts = std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(obj))
    {
      if (pending_actions) fail(r.begin, "two action collections in a row");
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
      if (pending_actions) fail(r.begin, "an observation follows an action collection");
      entry.observations = mrpt::obs::CSensoryFrame::Create();
      entry.observations->insert(obs);
    }
    else
    {
      fail(r.begin, std::string("unexpected object of class ") +
                        (obj ? obj->GetRuntimeClass()->className : "null"));
    }
    n++;
    if (!visit(entry)) break;
  }
  if (n == 0) throw std::runtime_error(path + ": the rawlog holds no entries");
  return n;
}

}  // namespace voxplore::common
