// mrpt-sim end to end: outputs, determinism, and errors for bad input.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>
#include <voxplore/apps/SimApp.h>
#include <voxplore/apps/app_common.h>
#include <voxplore/common/rawlog_io.h>
#include <voxplore/common/trajectory_io.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>
#include <vector>

#include "test_worlds.h"

using namespace voxplore;
namespace fs = std::filesystem;

namespace
{
std::string tmp(const std::string& name) { return test::tempPath(name); }

std::string writeFile(const std::string& name, const std::string& text)
{
  const auto p = tmp(name);
  std::ofstream(p) << text;
  return p;
}

apps::SimOptions shortTour(const std::string& out, int seed)
{
  apps::SimOptions o;
  o.world = test::sourceDir() + "/simulated_worlds/dlr_test_room.world";
  o.waypoints = writeFile("short_tour.txt", "# 1.2 m then a turn\n2.0 2.8\n2.0 2.8 30\n");
  o.config = test::sourceDir() + "/config/sim.ini";
  o.out_dir = tmp(out);
  o.seed = seed;
  o.quiet = true;
  return o;
}

std::string errorOf(const apps::SimOptions& o)
{
  try
  {
    apps::SimApp{}.execute(o);
  }
  catch (const std::exception& e)
  {
    return e.what();
  }
  return {};
}
}  // namespace

TEST(SimApp, ShortTourWritesAllOutputs)
{
  const auto o = shortTour("sim_out_a", 3);
  const auto s = apps::SimApp{}.execute(o);
  // start + 3 pieces of <= 0.5 m to the first waypoint + 1 turn in place
  EXPECT_EQ(s.stops, 5u);
  EXPECT_EQ(s.collisions, 0u);
  EXPECT_EQ(s.blocked_segments, 0u);
  EXPECT_NEAR(s.path_length_m, 1.2, 0.05);
  for (const char* f : {"run.rawlog", "trajectory_gt.tum", "trajectory_odo.tum", "topview.png", "params.ini"})
    EXPECT_TRUE(fs::is_regular_file(fs::path(o.out_dir) / f)) << f;
  const auto gt = common::readTum(o.out_dir + "/trajectory_gt.tum");
  ASSERT_EQ(gt.size(), s.stops);
  EXPECT_NEAR(gt.front().pose.x(), 2.0, 1e-6);
  EXPECT_NEAR(gt.front().pose.y(), 4.0, 1e-6);
  EXPECT_NEAR(gt.back().pose.y(), 2.8, 0.011);
  EXPECT_NEAR(gt.back().pose.yaw(), mrpt::DEG2RAD(30.0), mrpt::DEG2RAD(1.01));
  std::size_t entries = 0;
  // Guarded, from a process that already runs the simulator's threads: the
  // reader's child is a fresh process then (a forked one once hung here
  // under ASan on a lock held at fork()).
  common::forEachRawlogEntry(o.out_dir + "/run.rawlog", [&](const common::RawlogEntry& e) {
    EXPECT_EQ(e.observations->size(), 9u);
    entries++;
    return true;
  });
  EXPECT_EQ(entries, s.stops);
}

TEST(SimApp, RawlogEditReadsOurRawlog)
{
  if (!fs::exists("/usr/bin/rawlog-edit")) GTEST_SKIP() << "rawlog-edit (mrpt-apps) not installed";
  const auto o = shortTour("sim_out_info", 1);
  apps::SimApp{}.execute(o);
  const auto log = tmp("rawlog_edit_info.txt");
  const std::string cmd =
      "rawlog-edit --info -i '" + o.out_dir + "/run.rawlog' > '" + log + "' 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << test::readFile(log);
  const auto text = test::readFile(log);
  EXPECT_NE(text.find("Actions/SensoryFrame format       : Yes"), std::string::npos) << text;
  EXPECT_NE(text.find("CAM0, CAM1, CAM2, CAM3, CAM4, CAM5, CAM6, CAM7, ODOMETRY"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("CAM7 /      5"), std::string::npos) << text;
}

TEST(SimApp, SameSeedSameRunDifferentSeedDifferentRun)
{
  apps::SimApp{}.execute(shortTour("sim_seed_a", 7));
  apps::SimApp{}.execute(shortTour("sim_seed_b", 7));
  apps::SimApp{}.execute(shortTour("sim_seed_c", 8));
  const auto a = test::readFile(tmp("sim_seed_a") + "/run.rawlog");
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a, test::readFile(tmp("sim_seed_b") + "/run.rawlog"));
  EXPECT_NE(a, test::readFile(tmp("sim_seed_c") + "/run.rawlog"));
  EXPECT_EQ(test::readFile(tmp("sim_seed_a") + "/trajectory_gt.tum"),
            test::readFile(tmp("sim_seed_b") + "/trajectory_gt.tum"));
}

TEST(SimApp, StartInsideAnObstacleNamesTheWorldFile)
{
  auto o = shortTour("sim_bad_start", 1);
  o.start = "5.0,0.6,0";  // footprint overlaps the cabinet on the south wall
  const auto msg = errorOf(o);
  EXPECT_NE(msg.find("dlr_test_room.world"), std::string::npos) << msg;
  EXPECT_NE(msg.find("start"), std::string::npos) << msg;
}

TEST(SimApp, BadInputsAreNamedErrors)
{
  auto o = shortTour("sim_bad", 1);
  o.world = "/nonexistent/world.world";
  EXPECT_NE(errorOf(o).find("/nonexistent/world.world"), std::string::npos);

  o = shortTour("sim_bad", 1);
  o.waypoints = writeFile("bad_wp.txt", "1 2\n3 four\n");
  const auto msg = errorOf(o);
  EXPECT_NE(msg.find("bad_wp.txt:2"), std::string::npos) << msg;

  o = shortTour("sim_bad", 1);
  o.config = writeFile("bad.ini", "[robot]\nmax_speed = 2\n");
  EXPECT_NE(errorOf(o).find("max_speed"), std::string::npos);

  o = shortTour("sim_bad", 1);
  o.robot = "tank";
  EXPECT_NE(errorOf(o).find("tank"), std::string::npos);

  o = shortTour("sim_bad", 1);
  o.out_dir = "/proc/voxplore_cannot_write_here";
  EXPECT_NE(errorOf(o).find("/proc/voxplore_cannot_write_here"), std::string::npos);
}

TEST(SimApp, CommandLineHelpAndErrors)
{
  const char* help[] = {"mrpt-sim", "--help"};
  EXPECT_EQ(apps::SimApp{}.run(2, help), 0);
  const char* missing[] = {"mrpt-sim", "--world", "x.world"};
  EXPECT_EQ(apps::SimApp{}.run(3, missing), 1);
  const char* bad_world[] = {"mrpt-sim", "--world", "/nonexistent.world", "--waypoints", "/x",
                             "--out", "/tmp/x"};
  EXPECT_EQ(apps::SimApp{}.run(7, bad_world), 1);
}

// ------------------------------------------------ SIGINT (issue 14)

namespace
{
std::size_t lineCount(const std::string& path)
{
  std::ifstream f(path);
  std::size_t n = 0;
  for (std::string line; std::getline(f, line);) n += !line.empty() && line[0] != '#';
  return n;
}

std::size_t rawlogEntries(const std::string& path)
{
  std::size_t n = 0;
  common::forEachRawlogEntry(path,
                             [&](const common::RawlogEntry&)
                             {
                               n++;
                               return true;
                             });
  return n;
}
}  // namespace

TEST(SimApp, InterruptFlagEndsTheTourAfterTheCurrentStop)
{
  auto o = shortTour("sim_interrupt_flag", 1);
  apps::requestInterrupt();
  const auto s = apps::SimApp{}.execute(o);
  apps::clearInterrupt();
  EXPECT_TRUE(s.interrupted);
  EXPECT_EQ(s.stops, 1u);  // the start scan only
  EXPECT_EQ(rawlogEntries(o.out_dir + "/run.rawlog"), 1u);
  EXPECT_EQ(common::readTum(o.out_dir + "/trajectory_gt.tum").size(), 1u);
}

TEST(SimApp, SigintStopsMrptSimWithAReadableRawlog)
{
  const std::string bin = std::string(VOXPLORE_BIN_DIR) + "/mrpt-sim";
  if (!fs::exists(bin)) GTEST_SKIP() << "not built: " << bin;
  // 200 legs of 1.2 m (600 stops): far longer than the test waits.
  std::string legs;
  for (int i = 0; i < 100; i++) legs += "2.0 2.8\n2.0 4.0\n";
  const auto wps = writeFile("sigint_tour.txt", legs);
  const auto out = tmp("sim_sigint");
  fs::remove_all(out);
  const auto log = tmp("sim_sigint.log");
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0)
  {
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, 1);
    dup2(fd, 2);
    const std::string world = test::sourceDir() + "/simulated_worlds/dlr_test_room.world";
    const std::string cfg = test::sourceDir() + "/config/sim.ini";
    execl(bin.c_str(), bin.c_str(), "--world", world.c_str(), "--waypoints", wps.c_str(),
          "--config", cfg.c_str(), "--out", out.c_str(), "--quiet", static_cast<char*>(nullptr));
    _exit(127);
  }
  // Wait for 3 stops in the ground-truth trajectory (flushed after each stop).
  const auto t0 = std::chrono::steady_clock::now();
  int st = 0;
  bool exited = false;
  while (lineCount(out + "/trajectory_gt.tum") < 3 &&
         std::chrono::steady_clock::now() - t0 < std::chrono::seconds(120))
  {
    if (waitpid(pid, &st, WNOHANG) == pid)
    {
      exited = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_FALSE(exited) << "mrpt-sim exited before the signal:\n" << test::readFile(log);
  kill(pid, SIGINT);
  while (waitpid(pid, &st, WNOHANG) != pid &&
         std::chrono::steady_clock::now() - t0 < std::chrono::seconds(240))
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  if (waitpid(pid, &st, WNOHANG) == 0)  // still running: do not leak it
  {
    kill(pid, SIGKILL);
    waitpid(pid, &st, 0);
    FAIL() << "mrpt-sim did not stop after SIGINT:\n" << test::readFile(log);
  }
  const std::string text = test::readFile(log);
  ASSERT_TRUE(WIFEXITED(st)) << "killed by signal " << WTERMSIG(st) << "\n" << text;
  EXPECT_EQ(WEXITSTATUS(st), apps::kExitInterrupted) << text;
  EXPECT_NE(text.find("mrpt-sim: interrupted after"), std::string::npos) << text;
  const auto stops = common::readTum(out + "/trajectory_gt.tum").size();
  EXPECT_GE(stops, 3u);
  EXPECT_LT(stops, 100u) << "stopped early, not at the natural end";
  EXPECT_EQ(rawlogEntries(out + "/run.rawlog"), stops);  // every stop, none half-written
  EXPECT_EQ(common::readTum(out + "/trajectory_odo.tum").size(), stops);
  EXPECT_TRUE(fs::is_regular_file(out + "/topview.png"));
}
