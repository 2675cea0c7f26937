/* voxplore — a rawlog's objects, each deserialised by MRPT first in a child
 * process (started by rawlog_child.cpp). MRPT 2.5.8's deserialisation is not safe on corrupt bytes (a
 * null dereference in CActionRobotMovement2D::serializeFrom, length fields
 * that allocate GBs unchecked: fuzz/README.md), and no framing check of ours
 * can vouch for every class's payload. So the child parses the file ahead of
 * us and reports after each object "object k ok, ends at byte X" or "failed:
 * reason"; we parse object k only once the child has read it whole, and a
 * child that dies (signal, limit) is an error naming the object. */
#include "rawlog_objects.h"

#include "rawlog_child.h"

#include <fcntl.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/registerAllClasses.h>
#include <mrpt/obs/registerAllClasses.h>
#include <mrpt/serialization/CArchive.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <new>
#include <stdexcept>

namespace voxplore::common::detail
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
    if (got < count) hit_end_ = true;
    return got == count ? count : 0;
  }
  /// Bytes taken from the underlying (decompressed) stream so far.
  uint64_t consumed() const { return consumed_; }
  /// A read came short: the file ended (or the gzip stream broke) inside a field.
  bool hitEnd() const { return hit_end_; }
  size_t Write(const void*, size_t) override { return 0; }
  uint64_t Seek(int64_t offset, TSeekOrigin origin) override { return in_.Seek(offset, origin); }
  uint64_t getTotalBytesCount() const override { return in_.getTotalBytesCount(); }
  uint64_t getPosition() const override { return in_.getPosition(); }

 private:
  mrpt::io::CStream& in_;
  uint64_t consumed_ = 0;
  bool hit_end_ = false;
};

/// MRPT's reader over one rawlog file (gzip detected by CFileGZInputStream).
class ArchiveReader
{
 public:
  explicit ArchiveReader(const std::string& path)
  {
    // Every class a rawlog may hold, whatever the program links: without
    // this, a binary that uses few MRPT classes reads the same file differently
    // ("class ... not registered", found by the tests).
    static const bool registered = (mrpt::obs::registerAllClasses_mrpt_obs(),
                                    mrpt::maps::registerAllClasses_mrpt_maps(), true);
    (void)registered;
    if (!in_.open(path)) throw std::runtime_error("cannot open rawlog file '" + path + "'");
  }

  ObjectRead read()
  {
    ObjectRead r;
    r.begin = exact_.consumed();
    auto failed = [&](const std::string& reason, const std::string& details) {
      r.kind = ObjectRead::Kind::Failed;
      r.reason = reason;
      r.details = details;
      return r;
    };
    try
    {
      r.object = arch_->ReadObject();
    }
    catch (const mrpt::serialization::CExceptionEOF& e)
    {
      // MRPT throws EOF also for a nested object's missing header: a file cut
      // there is truncated, not complete (found by tests on every cut length).
      if (exact_.consumed() == r.begin) return r;  // Kind::End
      return failed("the file ends inside an object (truncated)", e.what());
    }
    catch (const std::bad_alloc& e)
    {
      return failed("corrupt object: a length field asks for more memory than allowed (" +
                        std::string(e.what()) + ")",
                    e.what());
    }
    catch (const std::exception& e)
    {
      if (exact_.hitEnd())  // MRPT wanted bytes past the end of the file
        return failed("the file ends inside an object (truncated)", e.what());
      return failed("corrupt object: " + summaryLineOf(e.what()), e.what());
    }
    catch (...)
    {
      return failed("corrupt object: unknown exception", {});
    }
    r.kind = ObjectRead::Kind::Object;
    r.end = exact_.consumed();
    return r;
  }

  uint64_t consumed() const { return exact_.consumed(); }

 private:
  mrpt::io::CFileGZInputStream in_;
  AllOrNothingInput exact_{in_};
  mrpt::serialization::CArchive::UniquePtr arch_ =
      mrpt::serialization::archiveUniquePtrFrom(exact_);
};

// ---------------------------------------------------------------- the pipe

/// What the child sends after each object: this header, then `text_len` bytes
/// "reason\0details".
struct RecordHeader
{
  std::uint32_t kind;
  std::uint32_t text_len;
  std::uint64_t begin;
  std::uint64_t end;
};
constexpr std::size_t kMaxText = 64 * 1024;

/// Writes everything or returns false (reader gone: EPIPE). EINTR-safe.
bool writeAll(int fd, const void* data, std::size_t n)
{
  const auto* p = static_cast<const char*>(data);
  while (n > 0)
  {
    const ssize_t w = ::write(fd, p, n);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) return false;
    p += w;
    n -= static_cast<std::size_t>(w);
  }
  return true;
}

/// Reads exactly n bytes; false at end of file or error. EINTR-safe.
bool readAll(int fd, void* data, std::size_t n)
{
  auto* p = static_cast<char*>(data);
  while (n > 0)
  {
    const ssize_t r = ::read(fd, p, n);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return false;
    p += r;
    n -= static_cast<std::size_t>(r);
  }
  return true;
}

bool sendRecord(int fd, const ObjectRead& r)
{
  std::string text = r.reason;
  text.push_back('\0');
  text += r.details.substr(0, kMaxText - text.size());
  const RecordHeader h{static_cast<std::uint32_t>(r.kind), static_cast<std::uint32_t>(text.size()),
                       r.begin, r.end};
  return writeAll(fd, &h, sizeof(h)) && writeAll(fd, text.data(), text.size());
}

}  // namespace

// ---------------------------------------------------------------- the child

void childMain(const std::string& path, int fd, pid_t parent, const RawlogReadOptions& opts) noexcept
{
  prepareChild(parent, opts);
  try
  {
    ArchiveReader reader(path);
    for (;;)
    {
      setAlarm(opts.object_timeout_ms);
      ObjectRead r = reader.read();
      setAlarm(0);
      r.object.reset();
      if (!sendRecord(fd, r) || r.kind != ObjectRead::Kind::Object) break;
    }
  }
  catch (const std::exception& e)
  {
    ObjectRead r;
    r.kind = ObjectRead::Kind::Failed;
    r.reason = summaryLineOf(e.what());
    r.details = e.what();
    sendRecord(fd, r);
  }
  catch (...)
  {
  }
  ::_exit(0);  // no atexit handlers, no flushing of the parent's stdio buffers
}

// ---------------------------------------------------------------- the parent

struct ObjectReader::Impl
{
  RawlogReadOptions opts;
  ArchiveReader reader;
  pid_t child = -1;
  int fd = -1;      ///< read end of the child's pipe
  bool reaped = false;

  Impl(const std::string& path, const RawlogReadOptions& o) : opts(o), reader(path)
  {
    if (!opts.isolate) return;
    int p[2];
    if (::pipe2(p, O_CLOEXEC) != 0)
      throw std::runtime_error("cannot read '" + path + "': pipe: " + std::strerror(errno));
    child = startChild(path, p[1], p[0], opts);
    if (child < 0)
    {
      const int err = errno;
      ::close(p[0]);
      ::close(p[1]);
      throw std::runtime_error("cannot read '" + path + "': fork: " + std::strerror(err));
    }
    ::close(p[1]);
    fd = p[0];
  }

  ~Impl()
  {
    if (fd >= 0) ::close(fd);  // a child blocked on write gets EPIPE / SIGPIPE
    if (child > 0 && !reaped)
    {
      ::kill(child, SIGKILL);  // not reaped yet: the pid is still ours
      reap();
    }
  }

  int reap()
  {
    int status = 0;
    while (::waitpid(child, &status, 0) < 0 && errno == EINTR)
    {
    }
    reaped = true;
    return status;
  }

  ObjectRead failed(std::uint64_t at, std::string reason, std::string details)
  {
    ObjectRead r;
    r.kind = ObjectRead::Kind::Failed;
    r.begin = at;
    r.reason = std::move(reason);
    r.details = std::move(details);
    return r;
  }

  ObjectRead next()
  {
    if (!opts.isolate) return reader.read();
    const std::uint64_t at = reader.consumed();
    RecordHeader h{};
    std::string text;
    bool got = readAll(fd, &h, sizeof(h)) && h.text_len <= kMaxText;
    if (got)
    {
      text.resize(h.text_len);
      got = readAll(fd, text.data(), text.size());
    }
    if (!got)  // the child died on this object, before its verdict
    {
      const int status = reap();
      std::string how = WIFSIGNALED(status)
                            ? "was killed by signal " + std::to_string(WTERMSIG(status)) + " (" +
                                  ::strsignal(WTERMSIG(status)) + ")"
                            : "exited with code " + std::to_string(WEXITSTATUS(status));
      return failed(at, describeChildEnd(status, opts),
                    "the child process that deserializes the rawlog first (pid " +
                        std::to_string(child) + ") " + how + " while it read the object at byte " +
                        std::to_string(at) + " (no message: it died inside MRPT)");
    }
    const auto kind = static_cast<ObjectRead::Kind>(h.kind);
    const auto nul = text.find('\0');
    if (h.begin != at)
      return failed(at, "internal error: the guard process read from byte " +
                            std::to_string(h.begin), {});
    if (kind == ObjectRead::Kind::Object)
    {
      ObjectRead r = reader.read();  // the child read these bytes whole: safe
      if (r.kind == ObjectRead::Kind::Object && r.end == h.end) return r;
      return failed(at, "the file changed while it was read (object read differently twice)",
                    r.details);
    }
    ObjectRead r;
    r.kind = kind == ObjectRead::Kind::End ? kind : ObjectRead::Kind::Failed;
    r.begin = at;
    r.reason = text.substr(0, nul);
    if (nul != std::string::npos) r.details = text.substr(nul + 1);
    return r;
  }
};

ObjectReader::ObjectReader(const std::string& path, const RawlogReadOptions& opts)
    : impl_(std::make_unique<Impl>(path, opts))
{
}

ObjectReader::~ObjectReader() = default;

ObjectRead ObjectReader::next() { return impl_->next(); }

}  // namespace voxplore::common::detail
