// Configuration: every config/*.ini loads, save/load round trips, and bad
// keys or values are errors naming the file and the key.
#include <gtest/gtest.h>
#include <voxplore/sim/worldgen.h>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <voxplore/common/config.h>
#include <voxplore/apps/ExploreApp.h>
#include <voxplore/exploration/Planner.h>
#include <voxplore/mapping/SlamIcp.h>
#include <voxplore/navigation/DriverParams.h>
#include <voxplore/sim/SimConfig.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "test_worlds.h"

using namespace voxplore;
namespace fs = std::filesystem;

namespace
{
std::string saved(const sim::SimConfig& c)
{
  mrpt::config::CConfigFileMemory m;
  c.save(m);
  return m.getContent();
}

std::string errorOf(const std::string& ini_text)
{
  const auto path = test::tempPath("bad_config.ini");
  std::ofstream(path) << ini_text;
  try
  {
    mrpt::config::CConfigFile cfg(path);
    sim::SimConfig::load(cfg);
  }
  catch (const std::exception& e)
  {
    return e.what();
  }
  return {};
}
}  // namespace

TEST(Config, EveryIniInConfigLoads)
{
  std::size_t n = 0;
  for (const auto& entry : fs::directory_iterator(test::sourceDir() + "/config"))
  {
    if (entry.path().extension() != ".ini") continue;
    SCOPED_TRACE(entry.path().string());
    const auto cfg = common::openIniFile(entry.path().string());
    // Every section must belong to a known Parameters struct, and each
    // struct present must load (keys and values checked).
    std::set<std::string> known = {"robot", "cameras", "simulator"};
    for (const auto& sec : mapping::SlamIcpParams::sections()) known.insert(sec);
    for (const auto& sec : exploration::PlannerParams::sections()) known.insert(sec);
    for (const auto& sec : navigation::DriverParams::sections()) known.insert(sec);
    known.insert(apps::ExploreParams::section());
    known.insert("worldgen");
    EXPECT_NO_THROW(common::assertKnownSections(*cfg, known));
    sim::WorldGenParams worldgen;
    EXPECT_NO_THROW(common::loadChecked(worldgen, *cfg, "worldgen"));
    EXPECT_NO_THROW(sim::SimConfig::load(*cfg));
    mapping::SlamIcpParams slam;
    EXPECT_NO_THROW(slam.load(*cfg));
    exploration::PlannerParams planner;
    EXPECT_NO_THROW(planner.load(*cfg));
    navigation::DriverParams nav;
    EXPECT_NO_THROW(common::loadChecked(nav, *cfg, "navigation"));
    n++;
  }
  EXPECT_GE(n, 2u);
}

TEST(Config, SaveThenLoadGivesTheSameParameters)
{
  for (const char* profile : {"omnirob", "compact"})
  {
    auto c = sim::SimConfig::defaults(profile);
    c.robot.max_v_mps = 0.37;
    c.cameras.range_noise_sigma_m = 0.004;
    c.sim.seed = 99;
    c.sim.scan_every_m = 0.7;
    mrpt::config::CConfigFileMemory m;
    c.save(m);
    const auto back = sim::SimConfig::load(m);
    EXPECT_EQ(saved(back), saved(c)) << profile;
  }
}

TEST(Config, CompactProfileMovesTheCameraRing)
{
  mrpt::config::CConfigFileMemory empty;
  const auto c = sim::SimConfig::load(empty, std::string("compact"));
  for (const auto& m : c.cameras.mounts)
    EXPECT_LE(std::hypot(m.x(), m.y()), c.robot.footprint().circumradius() + 1e-9);
}

// config/sim.ini sets the omniRob's body under [robot]; with --robot compact
// the ini wins, and the tool must be able to say which keys did.
TEST(Config, BodyKeysThatOverrideAGivenProfileAreListed)
{
  const auto cfg = common::openIniFile(std::string(VOXPLORE_SOURCE_DIR) + "/config/sim.ini");
  const auto c = sim::SimConfig::load(*cfg, std::string("compact"));
  ASSERT_FALSE(c.profile_overridden.empty());
  EXPECT_EQ(c.profile_overridden.front().rfind("length_m = 1.2 (compact: ", 0), 0u)
      << c.profile_overridden.front();
  const std::string warning = c.profileOverrideWarning("config/sim.ini");
  EXPECT_NE(warning.find("--robot compact, but [robot] in config/sim.ini sets length_m = 1.2"),
            std::string::npos)
      << warning;
  EXPECT_TRUE(sim::SimConfig::load(*cfg, std::string("omnirob")).profile_overridden.empty());
  EXPECT_EQ(sim::SimConfig::load(*cfg, std::string("omnirob")).profileOverrideWarning("x.ini"), "");
  EXPECT_TRUE(sim::SimConfig::load(*cfg).profile_overridden.empty());  // the ini's own profile
  mrpt::config::CConfigFileMemory only_profile;
  only_profile.write("robot", "profile", "omnirob");
  EXPECT_TRUE(sim::SimConfig::load(only_profile, std::string("compact")).profile_overridden.empty());
}

TEST(Config, UnknownKeyIsAnErrorNamingFileAndKey)
{
  const auto msg = errorOf("[robot]\nlenght_m = 1.0\n");
  EXPECT_NE(msg.find("bad_config.ini"), std::string::npos) << msg;
  EXPECT_NE(msg.find("lenght_m"), std::string::npos) << msg;
  EXPECT_NE(msg.find("length_m"), std::string::npos) << "suggests the right key: " << msg;
}

TEST(Config, WrongTypeAndOutOfRangeValuesAreErrors)
{
  auto msg = errorOf("[simulator]\ndt_s = fast\n");
  EXPECT_NE(msg.find("dt_s"), std::string::npos) << msg;
  msg = errorOf("[cameras]\nnum_cameras = 0\n");
  EXPECT_NE(msg.find("num_cameras"), std::string::npos) << msg;
  msg = errorOf("[cameras]\nmin_range_m = 8\n");
  EXPECT_NE(msg.find("min_range_m"), std::string::npos) << msg;
  msg = errorOf("[robot]\nwidth_m = -1\n");
  EXPECT_NE(msg.find("bad_config.ini"), std::string::npos) << msg;
  msg = errorOf("[cameras]\nnum_cameras = 2\ncam0_pose = 0 0 0.6 0 15 0\n");
  EXPECT_NE(msg.find("cam1_pose"), std::string::npos) << msg;
}

TEST(Config, ExplicitCameraPosesAreUsed)
{
  mrpt::config::CConfigFileMemory m;
  m.write("cameras", "num_cameras", 2);
  m.write("cameras", "cam0_pose", "0.5 0 0.6 0 15 0");
  m.write("cameras", "cam1_pose", "-0.5 0 0.6 180 15 0");
  const auto c = sim::SimConfig::load(m);
  ASSERT_EQ(c.cameras.mounts.size(), 2u);
  EXPECT_NEAR(c.cameras.mounts[1].x(), -0.5, 1e-12);
  EXPECT_NEAR(std::abs(c.cameras.mounts[1].yaw()), M_PI, 1e-9);
}

TEST(Config, SlamIcpParamsRoundTrip)
{
  mapping::SlamIcpParams p;
  p.metaview.d_min_m = 0.03;
  p.metaview.d_dup_2d_m = 0.07;
  p.icp.d_max_m = 0.4;
  p.icp.max_correction_yaw = mrpt::DEG2RAD(7.0);
  p.octomap.l_res_m = 0.08;
  p.octomap.invalid_free_range_m = 2.0;
  p.cloud.z_min_m = 0.12;
  mrpt::config::CConfigFileMemory m1, m2;
  p.save(m1);
  mapping::SlamIcpParams q;
  q.load(m1);
  q.save(m2);
  EXPECT_EQ(m1.getContent(), m2.getContent());
  EXPECT_NEAR(q.icp.max_correction_yaw, mrpt::DEG2RAD(7.0), 1e-12);
  EXPECT_EQ(q.octomap.l_res_m, 0.08);
  EXPECT_EQ(q.metaview.d_dup_2d_m, 0.07);
}

TEST(Config, SlamIcpParamsRejectBadValues)
{
  const auto path = test::tempPath("bad_slam.ini");
  for (const char* text : {"[octomap]\nl_res_m = -0.05\n", "[octomap]\nth_free = 250\n",
                           "[icp]\nd_max_m = abc\n", "[metaview]\nd_mn_m = 0.02\n",
                           "[metaview]\nd_dup_2d_m = -0.05\n"})
  {
    std::ofstream(path) << text;
    mrpt::config::CConfigFile cfg(path);
    mapping::SlamIcpParams p;
    try
    {
      p.load(cfg);
      ADD_FAILURE() << "no error for: " << text;
    }
    catch (const std::exception& e)
    {
      EXPECT_NE(std::string(e.what()).find("bad_slam.ini"), std::string::npos) << e.what();
    }
  }
}

// MRPT's CConfigFile returned the comment of a key left empty ("navlog_dir =
// // ...") as its value: every drive then logged into a directory named
// after the comment. openIniFile's reader gives the empty value.
TEST(Config, AKeyLeftEmptyBeforeItsCommentIsEmpty)
{
  const auto path = test::tempPath("empty_before_comment.ini");
  std::ofstream(path) << "[navigation]\n"
                         "navlog_dir      =      // where the logs go; empty = off\n"
                         "holonomic_method = CHolonomicFullEval   // kept\n"
                         "[explore]\n"
                         "x = 3 // three\n";
  const auto trim = [](const std::string& v)
  {
    const auto b = v.find_first_not_of(" \t"), e = v.find_last_not_of(" \t");
    return b == std::string::npos ? std::string() : v.substr(b, e - b + 1);
  };
  const auto cfg = common::openIniFile(path);
  EXPECT_EQ(cfg->read_string("navigation", "navlog_dir", "unset"), "");
  EXPECT_EQ(trim(cfg->read_string("navigation", "holonomic_method", "")),
            "CHolonomicFullEval");
  EXPECT_EQ(cfg->read_double("explore", "x", 0), 3.0);
  navigation::DriverParams d;
  d.loadFromConfigFile(*cfg, "navigation");
  EXPECT_TRUE(d.navlog_dir.empty()) << "navlog_dir read as '" << d.navlog_dir << "'";
  // Every shipped ini: no key reads as a comment.
  for (const auto& e : fs::directory_iterator(std::string(VOXPLORE_SOURCE_DIR) + "/config"))
  {
    if (e.path().extension() != ".ini") continue;
    const auto ini = common::openIniFile(e.path().string());
    std::vector<std::string> sections, keys;
    ini->getAllSections(sections);
    for (const auto& s : sections)
    {
      ini->getAllKeys(s, keys);
      for (const auto& k : keys)
        EXPECT_NE(trim(ini->read_string(s, k, "")).rfind("//", 0), 0u)
            << e.path() << " [" << s << "] " << k;
    }
  }
}
