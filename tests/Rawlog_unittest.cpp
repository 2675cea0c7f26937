// Rawlogs written by the simulator round-trip through MRPT's reader and ours;
// truncated and missing files give errors naming the file and entry.
#include <gtest/gtest.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CRawlog.h>
#include <voxplore/common/rawlog_io.h>
#include <voxplore/sim/Simulator.h>

#include <filesystem>
#include <fstream>

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
