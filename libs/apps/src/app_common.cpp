#include <voxplore/apps/app_common.h>

#include <signal.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>

namespace voxplore::apps
{
namespace
{
volatile std::sig_atomic_t g_interrupted = 0;

extern "C" void onInterruptSignal(int)
{
  g_interrupted = 1;  // the only thing a handler may do safely; SA_RESETHAND re-arms SIG_DFL
}
}  // namespace

void installInterruptHandler()
{
  struct sigaction sa = {};
  sa.sa_handler = onInterruptSignal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESETHAND;  // a second signal terminates at once
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

bool interruptRequested() { return g_interrupted != 0; }
void requestInterrupt() { g_interrupted = 1; }
void clearInterrupt() { g_interrupted = 0; }

int runGuarded(const std::string& app_name, const std::function<int()>& body)
{
  try
  {
    return body();
  }
  catch (const std::exception& e)
  {
    // One line: a Progress line was ended by its destructor during unwinding.
    std::cerr << app_name << ": error: " << e.what() << std::endl;
    return 1;
  }
}

int exitCodeAfterFailedParse(int argc, const char* const* argv)
{
  for (int i = 1; i < argc; i++)
  {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help" || a == "--version") return 0;
  }
  return 1;
}

void prepareOutputDir(const std::string& dir)
{
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir))
    throw std::runtime_error("cannot create output directory '" + dir + "': " + ec.message());
  const auto probe = fs::path(dir) / ".voxplore_write_test";
  {
    std::ofstream f(probe);
    if (!f) throw std::runtime_error("output directory '" + dir + "' is not writable");
  }
  fs::remove(probe, ec);
}

}  // namespace voxplore::apps
