/* voxplore — a rawlog's objects, each deserialised by MRPT first in a forked
 * child process. MRPT 2.5.8's deserialisation is not safe on corrupt bytes (a
 * null dereference in CActionRobotMovement2D::serializeFrom, length fields
 * that allocate GBs unchecked: fuzz/README.md), and no framing check of ours
 * can vouch for every class's payload. So the child parses the file ahead of
 * us and reports after each object "object k ok, ends at byte X" or "failed:
 * reason"; we parse object k only once the child has read it whole, and a
 * child that dies (signal, limit) is an error naming the object. */
#include "rawlog_objects.h"

#include <fcntl.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/registerAllClasses.h>
#include <mrpt/obs/registerAllClasses.h>
#include <mrpt/serialization/CArchive.h>
#include <signal.h>
#include <spawn.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <new>
#include <stdexcept>
#include <vector>

// Set by ASan/UBSan (and libFuzzer through them); absent otherwise. The child
// clears it so that a fault it survives by dying does not run the fuzzer's
// crash handling (writing a crash artifact) in the child.
extern "C" __attribute__((weak)) void __sanitizer_set_death_callback(void (*callback)(void));

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

// ---------------------------------------------------------------- the child

/// Lets the child's address space grow by `mb` at most from where it is now
/// (under ASan the baseline holds its terabytes of reserved shadow, so a
/// fixed RLIMIT_AS would not do). Above it, MRPT's allocations fail: a
/// std::bad_alloc, or a null pointer MRPT dereferences (it does not check).
void limitAddressSpace(std::size_t mb)
{
  unsigned long long pages = 0;
  if (FILE* f = std::fopen("/proc/self/statm", "r"))
  {
    if (std::fscanf(f, "%llu", &pages) != 1) pages = 0;
    std::fclose(f);
  }
  if (pages == 0) return;  // no /proc: no limit, the parent still survives
  rlimit lim{};
  if (::getrlimit(RLIMIT_AS, &lim) != 0) return;
  const auto want = static_cast<rlim_t>(pages) * static_cast<rlim_t>(::sysconf(_SC_PAGESIZE)) +
                    static_cast<rlim_t>(mb) * 1024 * 1024;
  if (lim.rlim_cur == RLIM_INFINITY || want < lim.rlim_cur) lim.rlim_cur = want;
  if (lim.rlim_max != RLIM_INFINITY && lim.rlim_cur > lim.rlim_max) lim.rlim_cur = lim.rlim_max;
  ::setrlimit(RLIMIT_AS, &lim);
}

/// SIGALRM (default action: the child dies, the parent names it) after `ms`; 0 cancels.
void setAlarm(unsigned ms)
{
  itimerval t{};
  t.it_value.tv_sec = ms / 1000;
  t.it_value.tv_usec = static_cast<suseconds_t>(ms % 1000) * 1000;
  ::setitimer(ITIMER_REAL, &t, nullptr);
}

[[noreturn]] void childMain(const std::string& path, int fd, pid_t parent,
                            const RawlogReadOptions& opts) noexcept
{
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);  // never outlive the reader
  if (::getppid() != parent) ::_exit(0);
  ::signal(SIGINT, SIG_IGN);  // Ctrl-C is the parent's: it stops between stops
  for (int sig : {SIGTERM, SIGALRM, SIGPIPE, SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT})
    ::signal(sig, SIG_DFL);  // die by the signal itself: the parent names it
  if (__sanitizer_set_death_callback) __sanitizer_set_death_callback(nullptr);
  if (!opts.child_output)
  {
    const int devnull = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
    if (devnull >= 0)
    {
      ::dup2(devnull, STDOUT_FILENO);
      ::dup2(devnull, STDERR_FILENO);
    }
  }
  limitAddressSpace(opts.object_memory_mb);
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

/// Why the child ended without a verdict on the object it was reading.
std::string describeChildEnd(int status, const RawlogReadOptions& opts)
{
  const std::string limit = std::to_string(opts.object_memory_mb) + " MB";
  if (WIFSIGNALED(status))
  {
    const int sig = WTERMSIG(status);
    const char* abbrev = ::sigabbrev_np(sig);
    const std::string name = std::string("SIG") + (abbrev ? abbrev : std::to_string(sig).c_str());
    if (sig == SIGALRM)
      return "MRPT spent more than " + std::to_string(opts.object_timeout_ms) +
             " ms on this object (a corrupt count?)";
    if (sig == SIGKILL)
      return "the process deserializing it was killed (SIGKILL, out of memory?)";
    return "MRPT crashed (" + name + ") while deserializing a corrupt object (a null pointer or " +
           "an allocation beyond the " + limit + " limit)";
  }
  if (WIFEXITED(status))
    return "MRPT aborted while deserializing a corrupt object (exit code " +
           std::to_string(WEXITSTATUS(status)) + ": a sanitizer report or an allocation beyond the " +
           limit + " limit)";
  return "the process deserializing it ended abnormally";
}

/// The environment variable that makes a fresh process the reader's child.
constexpr const char* kChildEnv = "VOXPLORE_RAWLOG_CHILD";
/// The pipe's write end in a spawned child.
constexpr int kChildFd = 3;

/// Threads of this process (/proc/self/task); 0 when it cannot be read.
std::size_t threadCount()
{
  std::size_t n = 0;
  std::error_code ec;
  for (auto it = std::filesystem::directory_iterator("/proc/self/task", ec);
       !ec && it != std::filesystem::directory_iterator(); it.increment(ec))
    n++;
  return n;
}

/// A multi-threaded caller's child: this program again (/proc/self/exe),
/// started fresh with kChildEnv, so that no lock another thread held at
/// fork() can deadlock it (seen under ASan: a forked child of a test that
/// had run the simulator's ray-casting threads hung on a good file).
/// The library constructor runChildIfAsked() turns it into childMain().
/// @return the child's pid, or -1 with errno set
pid_t spawnChild(const std::string& path, int write_fd, pid_t parent, const RawlogReadOptions& opts)
{
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec)
  {
    errno = ENOENT;
    return -1;
  }
  const std::string var = std::string(kChildEnv) + "=" + std::to_string(parent) + ":" +
                          std::to_string(opts.object_memory_mb) + ":" +
                          std::to_string(opts.object_timeout_ms) + ":" +
                          (opts.child_output ? "1" : "0") + ":" + path;
  std::vector<char*> envp;
  for (char** e = environ; e && *e; ++e)
    if (std::strncmp(*e, kChildEnv, std::strlen(kChildEnv)) != 0) envp.push_back(*e);
  envp.push_back(const_cast<char*>(var.c_str()));
  envp.push_back(nullptr);
  const std::string exe_path = exe.string();
  char* argv[] = {const_cast<char*>(exe_path.c_str()), nullptr};
  // dup2 onto kChildFd clears FD_CLOEXEC there, unless it is already that fd.
  const int from = write_fd == kChildFd ? ::fcntl(write_fd, F_DUPFD_CLOEXEC, kChildFd + 1) : write_fd;
  if (from < 0) return -1;
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_adddup2(&fa, from, kChildFd);
  pid_t pid = -1;
  const int err = ::posix_spawn(&pid, exe_path.c_str(), &fa, nullptr, argv, envp.data());
  posix_spawn_file_actions_destroy(&fa);
  if (from != write_fd) ::close(from);
  if (err != 0)
  {
    errno = err;
    return -1;
  }
  return pid;
}

/// In a process spawned by spawnChild(): be the child and never return to
/// main(). Runs as a library constructor, before the program's own code.
__attribute__((constructor)) void runChildIfAsked()
{
  const char* v = std::getenv(kChildEnv);
  if (!v) return;
  const std::string spec(v);
  ::unsetenv(kChildEnv);
  std::size_t at = 0;
  const auto field = [&]() {
    const std::size_t end = spec.find(':', at);
    const std::string f = spec.substr(at, end == std::string::npos ? std::string::npos : end - at);
    at = end == std::string::npos ? spec.size() : end + 1;
    return f;
  };
  try
  {
    const pid_t parent = static_cast<pid_t>(std::stol(field()));
    RawlogReadOptions opts;
    opts.object_memory_mb = std::stoul(field());
    opts.object_timeout_ms = static_cast<unsigned>(std::stoul(field()));
    opts.child_output = field() == "1";
    childMain(spec.substr(at), kChildFd, parent, opts);
  }
  catch (...)
  {
    ::_exit(2);  // a malformed request: the parent reports the child's end
  }
}
}  // namespace

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
    const pid_t parent = ::getpid();
    // fork() is cheap (the fuzzer reads thousands of files) and safe with one
    // thread; with more, a fresh process (spawnChild).
    const bool spawn = opts.fresh_child_when_threaded && threadCount() > 1;
    child = spawn ? spawnChild(path, p[1], parent, opts) : ::fork();
    if (child < 0)
    {
      const int err = errno;
      ::close(p[0]);
      ::close(p[1]);
      throw std::runtime_error("cannot read '" + path + "': fork: " + std::strerror(err));
    }
    if (child == 0 && !spawn)
    {
      ::close(p[0]);
      childMain(path, p[1], parent, opts);
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
