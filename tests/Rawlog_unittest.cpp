// Rawlogs written by the simulator round-trip through MRPT's reader and ours;
// truncated and missing files give errors naming the file and entry.
#include <gtest/gtest.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/io/zip.h>
#include <mrpt/obs/CRawlog.h>
#include <unistd.h>
#include <voxplore/common/rawlog_io.h>
#include <voxplore/sim/Simulator.h>

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <filesystem>
#include <iostream>
#include <fstream>
#include <optional>

#include "test_worlds.h"

using namespace voxplore;
namespace fs = std::filesystem;

namespace
{
std::string tempPath(const std::string& name)
{
  return test::tempPath(name);
}

std::vector<sim::ScanStop> writeSmallRawlog(const std::string& path)
{
  sim::Simulator simu(test::boxRoom(10, 8, 3, mrpt::poses::CPose2D(3, 4, 0)),
                      sim::RobotParams::omnirob(), sim::CameraRigParams{}, sim::SimulatorParams{});
  common::RawlogWriter w(path);
  std::vector<sim::ScanStop> stops;
  for (int i = 0; i < 4; i++)
  {
    if (i > 0)
    {
      EXPECT_EQ(simu.driveTo(3 + 0.5 * i, 4, std::nullopt), sim::DriveOutcome::Reached);
    }
    stops.push_back(simu.scan());
    w.write(*stops.back().actions, *stops.back().observations);
  }
  EXPECT_EQ(w.entries(), 4u);
  return stops;
}
}  // namespace

TEST(Rawlog, RoundTripsThroughMrptReader)
{
  const auto path = tempPath("roundtrip.rawlog");
  const auto stops = writeSmallRawlog(path);
  mrpt::obs::CRawlog log;
  ASSERT_TRUE(log.loadFromRawLogFile(path));
  ASSERT_EQ(log.size(), 8u);  // 4 x (actions, sensory frame)
  for (std::size_t i = 0; i < 4; i++)
  {
    mrpt::obs::CActionCollection::Ptr acts;
    mrpt::obs::CSensoryFrame::Ptr sf;
    size_t cursor = 2 * i;
    ASSERT_TRUE(log.getActionObservationPair(acts, sf, cursor));
    ASSERT_EQ(sf->size(), 9u);  // odometry + 8 cameras
    auto odo = sf->getObservationByClass<mrpt::obs::CObservationOdometry>();
    ASSERT_TRUE(odo);
    EXPECT_NEAR((odo->odometry - stops[i].odometry).norm(), 0.0, 1e-9);
    for (int c = 0; c < 8; c++)
    {
      auto scan = sf->getObservationByClass<mrpt::obs::CObservation3DRangeScan>(c);
      ASSERT_TRUE(scan);
      auto orig = stops[i].observations->getObservationByClass<mrpt::obs::CObservation3DRangeScan>(c);
      EXPECT_EQ(scan->sensorLabel, orig->sensorLabel);
      EXPECT_TRUE(scan->rangeImage == orig->rangeImage);
      EXPECT_EQ(scan->sensorPose, orig->sensorPose);
      EXPECT_EQ(scan->timestamp, orig->timestamp);
      EXPECT_FALSE(scan->hasPoints3D);
    }
  }
}

TEST(Rawlog, OurReaderStreamsEntries)
{
  const auto path = tempPath("stream.rawlog");
  writeSmallRawlog(path);
  std::size_t seen = 0;
  const auto n = common::forEachRawlogEntry(path, [&](const common::RawlogEntry& e) {
    EXPECT_EQ(e.index, seen);
    EXPECT_TRUE(e.actions);
    EXPECT_EQ(e.observations->size(), 9u);
    seen++;
    return true;
  });
  EXPECT_EQ(n, 4u);
  EXPECT_EQ(seen, 4u);
}

TEST(Rawlog, TruncatedFileNamesFileAndEntryAndKeepsEarlierEntries)
{
  const auto path = tempPath("truncated.rawlog");
  writeSmallRawlog(path);
  const auto size = fs::file_size(path);
  fs::resize_file(path, size - size / 5);  // cut inside the last entry
  std::size_t seen = 0;
  try
  {
    common::forEachRawlogEntry(path, [&](const common::RawlogEntry&) {
      seen++;
      return true;
    });
    FAIL() << "no error for a truncated rawlog";
  }
  catch (const std::runtime_error& e)
  {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("truncated.rawlog"), std::string::npos) << msg;
    EXPECT_NE(msg.find("entry 3"), std::string::npos) << msg;
  }
  EXPECT_EQ(seen, 3u);
}

TEST(Rawlog, MissingAndEmptyFilesAreNamedErrors)
{
  EXPECT_THROW(
      {
        try
        {
          common::forEachRawlogEntry("/nonexistent/x.rawlog", [](auto&) { return true; });
        }
        catch (const std::runtime_error& e)
        {
          EXPECT_NE(std::string(e.what()).find("/nonexistent/x.rawlog"), std::string::npos);
          throw;
        }
      },
      std::runtime_error);
  const auto empty = tempPath("empty.rawlog");
  std::ofstream(empty).close();
  EXPECT_THROW(common::forEachRawlogEntry(empty, [](auto&) { return true; }), std::runtime_error);
  const auto garbage = tempPath("garbage.rawlog");
  std::ofstream(garbage) << "this is not a rawlog at all, just some text\n";
  EXPECT_THROW(common::forEachRawlogEntry(garbage, [](auto&) { return true; }), std::runtime_error);
}

// Every cut of the last entry must stop at once with an error naming the file
// and the entry. Found by fuzz/fuzz_rawlog: MRPT's CArchive accepts a short
// read inside a field, so a file cut inside a uint32 count left the count's
// last bytes unset (a CActionCollection of up to 4e9 actions: minutes and tens
// of GB). Found by this test: a cut just before a nested object's header made
// MRPT throw end-of-file, which the reader took for a complete file.
TEST(Rawlog, EveryCutInsideTheLastEntryIsAnError)
{
  auto pair = [](double x)
  {
    mrpt::obs::CActionCollection acts;
    mrpt::obs::CActionRobotMovement2D move;
    move.computeFromOdometry(mrpt::poses::CPose2D(x, 0, 0),
                             mrpt::obs::CActionRobotMovement2D::TMotionModelOptions());
    acts.insert(move);
    auto sf = mrpt::obs::CSensoryFrame::Create();
    auto scan = mrpt::obs::CObservation3DRangeScan::Create();
    scan->hasRangeImage = true;
    scan->cameraParams.ncols = 4;
    scan->cameraParams.nrows = 3;
    scan->rangeImage.resize(3, 4);
    scan->rangeImage.fill(1500);
    sf->insert(scan);
    return std::make_pair(acts, sf);
  };
  const auto whole = tempPath("cut_whole.rawlog");
  std::uintmax_t first_size = 0;
  {
    common::RawlogWriter w(whole);  // flushed after each pair
    auto [a0, sf0] = pair(0.0);
    w.write(a0, *sf0);
    first_size = fs::file_size(whole);
    auto [a1, sf1] = pair(0.5);
    w.write(a1, *sf1);
  }
  const auto size = fs::file_size(whole);
  ASSERT_GT(size, first_size);
  std::ifstream in(whole, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto cut = tempPath("cut.rawlog");
  for (auto len = first_size + 1; len < size; ++len)
  {
    std::ofstream(cut, std::ios::binary | std::ios::trunc).write(bytes.data(), len);
    std::size_t seen = 0;
    try
    {
      common::forEachRawlogEntry(cut,
                                 [&](const common::RawlogEntry&)
                                 {
                                   seen++;
                                   return true;
                                 });
      ADD_FAILURE() << "no error for a rawlog cut at byte " << len << " of " << size;
    }
    catch (const std::runtime_error& e)
    {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("cut.rawlog"), std::string::npos) << msg;
      EXPECT_NE(msg.find("entry 1"), std::string::npos) << "cut at " << len << ": " << msg;
    }
    EXPECT_EQ(seen, 1u) << "cut at byte " << len;
  }
}

// ===================================================== issue 14: no crash on any rawlog
// MRPT 2.5.8 crashes or allocates GBs on these (fuzz/mrpt_crashes/, found by
// fuzz/fuzz_rawlog; fuzz/README.md). The reader parses every object in a child
// process first, so each is one error line naming the file, entry and offset.

namespace
{
std::string reproducer(const std::string& name)
{
  return test::sourceDir() + "/fuzz/mrpt_crashes/" + name + ".rawlog";
}

const std::vector<std::string> kReproducers = {"null_deref_CActionRobotMovement2D",
                                               "huge_alloc_string", "huge_alloc_CMatrixDynamic"};

/// The RawlogError of reading `path`, and the entries visited before it.
std::optional<common::RawlogError> readError(const std::string& path, std::size_t& seen)
{
  seen = 0;
  try
  {
    common::forEachRawlogEntry(path, [&](const common::RawlogEntry& e) {
      EXPECT_EQ(e.index, seen);
      seen++;
      return true;
    });
  }
  catch (const common::RawlogError& e)
  {
    return e;
  }
  return std::nullopt;
}

/// Why MRPT could not read a reproducer: it crashed or aborted in the child
/// (null dereference; a failed allocation under the child's memory limit, or
/// a sanitizer's out-of-memory report) or threw std::bad_alloc there.
bool isMrptFault(const std::string& msg)
{
  return msg.find("MRPT crashed (SIGSEGV)") != std::string::npos ||
         msg.find("MRPT aborted") != std::string::npos ||
         msg.find("std::bad_alloc") != std::string::npos;
}

std::size_t countChildren()  // our unreaped children, zombies included
{
  std::size_t n = 0;
  const auto self = std::to_string(::getpid());
  for (const auto& d : fs::directory_iterator("/proc"))
  {
    std::ifstream stat(d.path() / "stat");
    std::string pid, comm, state, ppid;
    if (stat >> pid >> comm >> state >> ppid && ppid == self) n++;
  }
  return n;
}

std::size_t countOpenFds()
{
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& d : fs::directory_iterator("/proc/self/fd")) n++;
  return n;
}
}  // namespace

TEST(Rawlog, MrptCrashReproducersAreOneLineErrorsNamingFileAndEntry)
{
  for (const auto& name : kReproducers)
  {
    std::size_t seen = 0;
    const auto err = readError(reproducer(name), seen);
    ASSERT_TRUE(err) << name << ": no error";
    const std::string msg = err->what();
    EXPECT_EQ(seen, 0u) << msg;
    EXPECT_EQ(err->entry(), 0u) << msg;
    EXPECT_EQ(err->byteOffset(), 0u) << msg;
    EXPECT_EQ(msg.find(reproducer(name) + ": entry 0 (byte offset 0): "), 0u) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    EXPECT_TRUE(isMrptFault(msg)) << msg;
    if (name.rfind("null_deref", 0) == 0)
    {
      EXPECT_NE(msg.find("MRPT "), std::string::npos) << msg;
      EXPECT_EQ(msg.find("bad_alloc"), std::string::npos) << msg;
    }
  }
}

// A caller with other threads gets a freshly started child (this program
// again) instead of a fork: the same verdicts, the good entries all read.
TEST(Rawlog, AMultiThreadedCallerIsStillProtected)
{
  std::mutex m;
  std::condition_variable cv;
  bool done = false;
  std::thread busy([&] {
    std::unique_lock<std::mutex> lock(m);
    cv.wait(lock, [&] { return done; });
  });
  const auto good = tempPath("good_threads.rawlog");
  writeSmallRawlog(good);
  std::size_t entries = 0;
  common::forEachRawlogEntry(good, [&](const common::RawlogEntry& e) {
    EXPECT_TRUE(e.observations);
    entries++;
    return true;
  });
  EXPECT_GT(entries, 0u);
  for (const auto& name : kReproducers)
  {
    std::size_t seen = 0;
    const auto err = readError(reproducer(name), seen);
    ASSERT_TRUE(err) << name << ": no error";
    const std::string msg = err->what();
    EXPECT_EQ(msg.find(reproducer(name) + ": entry 0 (byte offset 0): "), 0u) << msg;
    EXPECT_TRUE(isMrptFault(msg)) << msg;
  }
  {
    std::lock_guard<std::mutex> lock(m);
    done = true;
  }
  cv.notify_one();
  busy.join();
}

// The same bytes after good entries, plain and gzip: every good entry is
// visited, then the error names the next entry and where it starts.
TEST(Rawlog, GoodEntriesThenMrptCrashReproducerStopsExactlyThere)
{
  const auto good = tempPath("good_prefix.rawlog");
  writeSmallRawlog(good);
  const std::string prefix = test::readFile(good);
  for (const auto& name : kReproducers)
  {
    for (const bool gzip : {false, true})
    {
      const std::string plain = prefix + test::readFile(reproducer(name));
      std::vector<std::uint8_t> bytes(plain.begin(), plain.end());
      if (gzip)
      {
        std::vector<std::uint8_t> gz;
        ASSERT_TRUE(mrpt::io::zip::compress_gz_data_block(bytes, gz, 1));
        bytes.swap(gz);
      }
      const auto path = tempPath("prefix_then_" + name + (gzip ? ".gz.rawlog" : ".rawlog"));
      std::ofstream(path, std::ios::binary)
          .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
      std::size_t seen = 0;
      const auto err = readError(path, seen);
      ASSERT_TRUE(err) << path;
      const std::string msg = err->what();
      EXPECT_EQ(seen, 4u) << msg;
      EXPECT_EQ(err->entry(), 4u) << msg;
      EXPECT_EQ(err->byteOffset(), prefix.size()) << msg;
      const std::string where = path + ": entry 4 (byte offset " + std::to_string(prefix.size()) +
                                (gzip ? " of the decompressed stream" : "") + "): ";
      EXPECT_EQ(msg.find(where), 0u) << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
      EXPECT_TRUE(isMrptFault(msg)) << msg;
    }
  }
}

// MRPT's exceptions carry whole backtraces: the error keeps one line, the
// details keep MRPT's text.
TEST(Rawlog, MrptExceptionIsOneLineWithTheFullTextInDetails)
{
  const auto good = tempPath("good_then_garbage.rawlog");
  writeSmallRawlog(good);
  const auto size = fs::file_size(good);
  // 0x85: a class name of 5 characters follows (MRPT 2 header), which no class has
  std::ofstream(good, std::ios::binary | std::ios::app) << "\x85XXXXX and then garbage";
  std::size_t seen = 0;
  const auto err = readError(good, seen);
  ASSERT_TRUE(err);
  const std::string msg = err->what();
  EXPECT_EQ(seen, 4u) << msg;
  EXPECT_EQ(msg.find(good + ": entry 4 (byte offset " + std::to_string(size) + "): corrupt object: "),
            0u)
      << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  EXPECT_EQ(msg.find("===="), std::string::npos) << msg;
  EXPECT_NE(err->details().find("MRPT exception"), std::string::npos) << err->details();
  EXPECT_NE(err->details().find('\n'), std::string::npos) << err->details();
}

TEST(Rawlog, SummaryLineOfMrptExceptionJoinsTheMessages)
{
  EXPECT_EQ(common::summaryLineOf("==== MRPT exception ====\nMessage:  Outer thing\nOriginal "
                                  "exception:\n==== MRPT exception ====\nMessage:  inner why\n"
                                  "Location: x.cpp:3\nCall stack backtrace:\n[0] 0x1\n"),
            "Outer thing: inner why");
  EXPECT_EQ(common::summaryLineOf("\n  plain first line  \nsecond\n"), "plain first line");
  EXPECT_EQ(common::summaryLineOf(""), "(no message)");
  EXPECT_LE(common::summaryLineOf(std::string(5000, 'x')).size(), 303u);
}

// The fuzzer calls the reader millions of times: no descriptor or child
// process may be left behind, whether the file is good, stopped early, or
// crashes MRPT.
TEST(Rawlog, ManyReadsLeaveNoDescriptorsOrChildProcesses)
{
  const auto good = tempPath("many_reads.rawlog");
  writeSmallRawlog(good);
  const auto fds = countOpenFds();
  const auto children = countChildren();
  for (int i = 0; i < 10; i++)
  {
    std::size_t seen = 0;
    EXPECT_FALSE(readError(good, seen));
    EXPECT_EQ(seen, 4u);
    std::size_t early = 0;
    common::forEachRawlogEntry(good, [&](const common::RawlogEntry&) { return ++early < 2; });
    EXPECT_EQ(early, 2u);  // the child, still ahead, is killed and reaped
    for (const auto& name : kReproducers) EXPECT_TRUE(readError(reproducer(name), seen)) << name;
  }
  EXPECT_EQ(countOpenFds(), fds);
  EXPECT_EQ(countChildren(), children);
}

// Without isolation (RawlogReadOptions::isolate = false) the same reader
// gives the same entries: the guard changes nothing on good files.
TEST(Rawlog, IsolationChangesNothingOnAGoodFile)
{
  const auto good = tempPath("isolation.rawlog");
  writeSmallRawlog(good);
  common::RawlogReadOptions direct;
  direct.isolate = false;
  std::vector<std::size_t> sizes_direct, sizes_isolated;
  common::forEachRawlogEntry(good, [&](const common::RawlogEntry& e) {
    sizes_direct.push_back(e.observations->size());
    return true;
  }, direct);
  common::forEachRawlogEntry(good, [&](const common::RawlogEntry& e) {
    sizes_isolated.push_back(e.observations->size());
    return true;
  });
  EXPECT_EQ(sizes_direct, sizes_isolated);
  EXPECT_EQ(sizes_direct.size(), 4u);

  // The recorded tour, both ways: same entries; the time of each is printed
  // (the child runs ahead in parallel, so isolation costs about nothing).
  const auto recorded = test::sourceDir() + "/rawlogs/dlr_test_room/run.rawlog";
  std::vector<std::string> labels[2];
  double ms[2];
  for (int isolated = 0; isolated < 2; isolated++)
  {
    common::RawlogReadOptions o;
    o.isolate = isolated == 1;
    const auto t0 = std::chrono::steady_clock::now();
    common::forEachRawlogEntry(recorded, [&](const common::RawlogEntry& e) {
      for (const auto& obs : *e.observations) labels[isolated].push_back(obs->sensorLabel);
      return true;
    }, o);
    ms[isolated] = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  }
  EXPECT_EQ(labels[0], labels[1]);
  EXPECT_GT(labels[0].size(), 49u * 8u);
  std::cout << "[ rawlog ] dlr_test_room/run.rawlog (" << fs::file_size(recorded) / 1024
            << " KB): read in " << ms[0] << " ms directly, " << ms[1] << " ms with the child process\n";
}
