/* voxplore — the process that deserialises a rawlog ahead of its reader
 * (rawlog_objects.cpp): how it is started (fork, or this program afresh for a
 * multi-threaded caller), the limits it runs under, and how its end is told. */
#include "rawlog_child.h"

#include <fcntl.h>
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
#include <string>
#include <vector>

// Set by ASan/UBSan (and libFuzzer through them); absent otherwise. The child
// clears it so that a fault it survives by dying does not run the fuzzer's
// crash handling (writing a crash artifact) in the child.
extern "C" __attribute__((weak)) void __sanitizer_set_death_callback(void (*callback)(void));

namespace voxplore::common::detail
{
namespace
{
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


/// SIGALRM (default action: the child dies, the parent names it) after `ms`; 0 cancels.
void setAlarm(unsigned ms)
{
  itimerval t{};
  t.it_value.tv_sec = ms / 1000;
  t.it_value.tv_usec = static_cast<suseconds_t>(ms % 1000) * 1000;
  ::setitimer(ITIMER_REAL, &t, nullptr);
}

void prepareChild(pid_t parent, const RawlogReadOptions& opts)
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
}

pid_t startChild(const std::string& path, int write_fd, int read_fd, const RawlogReadOptions& opts)
{
  const pid_t parent = ::getpid();
  // fork() is cheap (the fuzzer reads thousands of files) and safe with one
  // thread; with more, a fresh process (spawnChild).
  if (opts.fresh_child_when_threaded && threadCount() > 1)
    return spawnChild(path, write_fd, parent, opts);
  const pid_t child = ::fork();
  if (child == 0)
  {
    ::close(read_fd);
    childMain(path, write_fd, parent, opts);  // never returns
  }
  return child;
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

}  // namespace voxplore::common::detail
