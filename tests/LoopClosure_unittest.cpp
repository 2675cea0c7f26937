// LoopCloser (libs/mapping): pose graph, detection against old keyframes,
// verification, relaxation; on synthetic planar scenes with a known truth.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/poses/CPose3DPDF.h>
#include <mrpt/random/RandomGenerators.h>
#include <mrpt/serialization/CArchive.h>
#include <voxplore/common/config.h>
#include <voxplore/common/trajectory_io.h>
#include <voxplore/mapping/LoopClosure.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <vector>

#include "test_worlds.h"

using mrpt::poses::CPose2D;
using voxplore::mapping::IcpParams;
using voxplore::mapping::IcpResult;
using voxplore::mapping::LoopCloser;
using voxplore::mapping::LoopClosureParams;
using voxplore::test::readCsv;

namespace
{
/// A scene: wall points (2 cm apart, three heights) of the given segments.
struct Scene
{
  std::vector<Eigen::Vector2d> pts;
  void wall(double x0, double y0, double x1, double y1)
  {
    const double len = std::hypot(x1 - x0, y1 - y0);
    const int n = static_cast<int>(len / 0.02);
    for (int i = 0; i <= n; i++)
      pts.emplace_back(x0 + (x1 - x0) * i / n, y0 + (y1 - y0) * i / n);
  }
  void box(double x, double y, double w, double h)
  {
    wall(x, y, x + w, y);
    wall(x + w, y, x + w, y + h);
    wall(x + w, y + h, x, y + h);
    wall(x, y + h, x, y);
  }
  /// The walls as a 2D map (z = 0), map frame.
  mrpt::maps::CSimplePointsMap map2d() const
  {
    mrpt::maps::CSimplePointsMap m;
    for (const auto& p : pts) m.insertPointFast(float(p.x()), float(p.y()), 0.f);
    m.mark_as_modified();
    return m;
  }
  /// The robot-frame cloud seen from the true pose: points within range_m.
  mrpt::maps::CSimplePointsMap cloudAt(const CPose2D& truth, double range_m = 6.0) const
  {
    mrpt::maps::CSimplePointsMap c;
    for (const auto& p : pts)
    {
      if (std::hypot(p.x() - truth.x(), p.y() - truth.y()) > range_m) continue;
      double lx = 0, ly = 0;
      truth.inverseComposePoint(p.x(), p.y(), lx, ly);
      for (const float z : {0.2f, 0.35f, 0.5f})
        c.insertPointFast(static_cast<float>(lx), static_cast<float>(ly), z);
    }
    c.mark_as_modified();
    return c;
  }
};

/// A ring corridor 3 m wide round a 24 x 14 m block, with posts and niches
/// that make every stretch distinct.
Scene ringScene()
{
  Scene s;
  s.box(0, 0, 30, 20);
  s.box(3, 3, 24, 14);
  mrpt::random::CRandomGenerator rng(7);
  for (int i = 0; i < 24; i++)
  {
    // Posts along the outer wall, irregular spacing.
    const double t = rng.drawUniform(0.0, 1.0);
    const int side = i % 4;
    const double w = rng.drawUniform(0.15, 0.4), d = rng.drawUniform(0.1, 0.3);
    if (side == 0) s.box(1 + t * 27, 0, w, d);
    if (side == 1) s.box(30 - d, 1 + t * 17, d, w);
    if (side == 2) s.box(1 + t * 27, 20 - d, w, d);
    if (side == 3) s.box(0, 1 + t * 17, d, w);
  }
  return s;
}

/// The true path round the ring corridor (0.5 m steps), heading along it.
std::vector<CPose2D> ringPath()
{
  const std::vector<Eigen::Vector2d> corners = {{1.5, 1.5}, {28.5, 1.5}, {28.5, 18.5},
                                                {1.5, 18.5}, {1.5, 1.5}, {9.0, 1.5}};
  std::vector<CPose2D> path;
  for (std::size_t c = 0; c + 1 < corners.size(); c++)
  {
    const Eigen::Vector2d a = corners[c], b = corners[c + 1];
    const double yaw = std::atan2(b.y() - a.y(), b.x() - a.x());
    const int n = static_cast<int>(std::round((b - a).norm() / 0.5));
    for (int i = 0; i < n; i++)
    {
      const Eigen::Vector2d p = a + (b - a) * (double(i) / n);
      path.emplace_back(p.x(), p.y(), yaw);
    }
  }
  return path;
}

IcpResult goodRegistration()
{
  IcpResult r;
  r.accepted = true;
  r.pairs = 2000;
  r.rms_m = 0.01;
  r.information = Eigen::Vector3d(1000, 1000, 4000).asDiagonal();
  return r;
}

struct RunResult
{
  std::vector<CPose2D> truth, before;
  std::size_t closures = 0, closed_at = 0, searched = 0, consistent = 0;
  double ate_before = 0, ate_after = 0;
};

/// Feeds the path with a drifting estimate (yaw drift per step, along-track
/// scale error) into a LoopCloser; returns the error before and after.
RunResult runRing(LoopCloser& lc, double yaw_drift_deg, double scale)
{
  const Scene scene = ringScene();
  RunResult out;
  out.truth = ringPath();
  CPose2D est = out.truth.front();
  double travel = 0;
  const IcpResult reg = goodRegistration();
  for (std::size_t k = 0; k < out.truth.size(); k++)
  {
    if (k > 0)
    {
      const CPose2D rel = out.truth[k] - out.truth[k - 1];
      const CPose2D drifted(rel.x() * scale, rel.y() * scale,
                            rel.phi() + mrpt::DEG2RAD(yaw_drift_deg));
      const CPose2D next = est + drifted;
      travel += std::hypot(next.x() - est.x(), next.y() - est.y());
      est = next;
    }
    out.before.push_back(est);
    const auto ev = lc.addKeyframe(k, est, est, travel, scene.cloudAt(out.truth[k]), 0.02,
                                   k > 0 ? &reg : nullptr);
    out.searched += ev.searched;
    out.consistent += ev.consistent;
    if (ev.closed)
    {
      out.closures++;
      if (!out.closed_at) out.closed_at = k;
      est = lc.keyframes().back().pose;
    }
  }
  double s0 = 0, s1 = 0;
  for (std::size_t k = 0; k < out.truth.size(); k++)
  {
    const auto& t = out.truth[k];
    s0 += std::pow(std::hypot(out.before[k].x() - t.x(), out.before[k].y() - t.y()), 2);
    const auto& a = lc.keyframes()[k].pose;
    s1 += std::pow(std::hypot(a.x() - t.x(), a.y() - t.y()), 2);
  }
  out.ate_before = std::sqrt(s0 / out.truth.size());
  out.ate_after = std::sqrt(s1 / out.truth.size());
  return out;
}
}  // namespace

TEST(LoopClosure, RingLoopIsClosedAndTheDriftRemoved)
{
  LoopClosureParams p;
  LoopCloser lc(p, IcpParams{});
  const auto r = runRing(lc, 0.04, 1.0);  // 0.04 deg per 0.5 m: 7 deg over the 88 m loop
  std::cout << "ring: " << r.truth.size() << " keyframes, closures " << r.closures
            << " (first at " << r.closed_at << "), searched " << r.searched << ", consistent "
            << r.consistent << ", ATE " << r.ate_before << " -> " << r.ate_after << " m"
            << std::endl;
  ASSERT_GE(r.closures, 1u);
  // Not before the robot is back where it started (keyframe 176 is 88 m on).
  EXPECT_GE(r.closed_at, 170u);
  EXPECT_GT(r.ate_before, 0.5);
  EXPECT_LT(r.ate_after, r.ate_before / 5);
  EXPECT_LT(r.ate_after, 0.1);
  EXPECT_GE(lc.numLoopEdges(), 2u);
}

namespace
{
/// The ring with every stop scanned twice from the same pose (a robot that
/// stops, scans, turns 2 deg and scans again): how far, by odometry, the
/// keyframe that closed the first loop was from the candidate it confirmed.
double closureDistanceFromCandidate(LoopCloser& lc, bool& closed)
{
  const Scene scene = ringScene();
  const std::vector<CPose2D> truth = ringPath();
  CPose2D est = truth.front();
  double travel = 0;
  const IcpResult reg = goodRegistration();
  std::size_t k = 0;
  CPose2D candidate_odo;
  closed = false;
  for (std::size_t i = 0; i < truth.size(); i++)
  {
    if (i > 0)
    {
      const CPose2D rel = truth[i] - truth[i - 1];
      const CPose2D next = est + CPose2D(rel.x(), rel.y(), rel.phi() + mrpt::DEG2RAD(0.04));
      travel += std::hypot(next.x() - est.x(), next.y() - est.y());
      est = next;
    }
    for (const double turn_deg : {0.0, 2.0})
    {
      const CPose2D turned(0, 0, mrpt::DEG2RAD(turn_deg));
      const CPose2D pose = est + turned;
      const std::size_t id = k++;
      const auto ev = lc.addKeyframe(id, pose, pose, travel, scene.cloudAt(truth[i] + turned),
                                     0.02, id > 0 ? &reg : nullptr);
      if (ev.candidate) candidate_odo = pose;
      if (ev.closed)
      {
        closed = true;
        return std::hypot(pose.x() - candidate_odo.x(), pose.y() - candidate_odo.y());
      }
    }
  }
  return -1;
}
}  // namespace

TEST(LoopClosure, AConfirmationMustComeFromAStopThatMovedAwayFromTheCandidate)
{
  // Off (the default): the second scan at the candidate's own stop confirms
  // it, seeing the submap as the candidate did (an aliased match repeats).
  LoopClosureParams off;
  LoopCloser lc_off(off, IcpParams{});
  bool closed = false;
  const double d_off = closureDistanceFromCandidate(lc_off, closed);
  ASSERT_TRUE(closed);
  EXPECT_LT(d_off, 0.05);
  // On: only a stop 0.3 m on (the next one, 0.5 m) confirms it.
  LoopClosureParams on;
  on.confirm_min_move_m = 0.3;
  on.confirm_min_turn = mrpt::DEG2RAD(30.0);
  LoopCloser lc_on(on, IcpParams{});
  const double d_on = closureDistanceFromCandidate(lc_on, closed);
  ASSERT_TRUE(closed);
  EXPECT_GE(d_on, 0.3);
  std::cout << "confirmed from " << d_off << " m (off), " << d_on << " m (on)" << std::endl;
}

namespace
{
/// The drifting ring, but the first candidate is never confirmed by a
/// correcting match: from the keyframe after it on, the estimate is already
/// on the old map (SlamIcp's registration against the metaview carried it
/// there, as in b5 omniRob nbv seed 2), so every later match is consistent.
/// The odometry keeps drifting. Returns the RMS error of the keyframes
/// before the candidate, as the graph holds them at the end.
double ateBeforeSnap(const LoopClosureParams& p, std::size_t& closures, std::string& messages)
{
  const Scene scene = ringScene();
  const std::vector<CPose2D> truth = ringPath();
  LoopCloser lc(p, IcpParams{});
  CPose2D est = truth.front(), odo = truth.front();
  double travel = 0;
  const IcpResult reg = goodRegistration();
  std::size_t candidate = 0;
  closures = 0;
  for (std::size_t k = 0; k < truth.size(); k++)
  {
    if (k > 0)
    {
      const CPose2D rel = truth[k] - truth[k - 1];
      const CPose2D drifted(rel.x(), rel.y(), rel.phi() + mrpt::DEG2RAD(0.04));
      const CPose2D next = est + drifted;
      travel += std::hypot(next.x() - est.x(), next.y() - est.y());
      est = next;
      odo = odo + drifted;
    }
    const auto ev = lc.addKeyframe(k, est, odo, travel, scene.cloudAt(truth[k]), 0.02,
                                   k > 0 ? &reg : nullptr);
    if (!ev.message.empty()) messages += std::to_string(k) + ": " + ev.message + "\n";
    if (ev.candidate && !candidate)
    {
      candidate = k;
      est = ev.matched;  // the registration's snap onto the old map
    }
    closures += ev.closed;
    if (ev.closed) est = lc.keyframes().back().pose;
  }
  double s = 0;
  for (std::size_t k = 0; k < candidate; k++)
  {
    const auto& a = lc.keyframes()[k].pose;
    s += std::pow(std::hypot(a.x() - truth[k].x(), a.y() - truth[k].y()), 2);
  }
  return candidate ? std::sqrt(s / double(candidate)) : -1;
}
}  // namespace

TEST(LoopClosure, AConsistentMatchThatAgreesWithTheCandidateClosesTheLoop)
{
  LoopClosureParams off;
  off.confirm_when_consistent = false;
  std::size_t closures_off = 0, closures_on = 0;
  std::string log_off, log_on;
  const double ate_off = ateBeforeSnap(off, closures_off, log_off);
  const double ate_on = ateBeforeSnap(LoopClosureParams{}, closures_on, log_on);
  std::cout << "drifted keyframes before the candidate: RMS " << ate_off << " m (off, "
            << closures_off << " closures), " << ate_on << " m (on, " << closures_on
            << " closures)" << std::endl;
  ASSERT_GT(ate_off, 0.0) << "no candidate:\n" << log_off;
  // Off: the candidate waits for a correcting match that never comes (a
  // later one, of the few centimetres drifted since the snap, closes
  // without moving the stretch); the drifted stretch stays as it was.
  EXPECT_EQ(log_off.find("'s candidate"), std::string::npos) << log_off;
  EXPECT_GT(ate_off, 0.5) << log_off;
  // On: the next keyframe's consistent match agrees with it and the loop
  // closes; the stretch before it is relaxed (0.027 m; 0.46 m while the
  // snap's edges stayed registration edges: the relaxation split the jump).
  EXPECT_GE(closures_on, 1u) << log_on;
  EXPECT_NE(log_on.find("'s candidate"), std::string::npos) << log_on;
  EXPECT_LT(ate_on, ate_off / 5);
  EXPECT_LT(ate_on, 0.1) << log_on;
}

namespace
{
/// The drifting ring (0.04 deg per 0.5 m), with loop detection out of
/// reach (search_radius_m 1 mm): coming back to the start, from the first
/// keyframe whose cloud sees the start's walls on, the estimate is the
/// truth, as SlamIcp's registration against the metaview puts it when it
/// pairs the old walls (an implicit closure, the fifty-first session's 44
/// returns). The odometry keeps drifting. Returns
/// the RMS error of the keyframes before the snap as the graph holds them.
double ateBeforeImplicitReturn(LoopClosureParams p, std::size_t& closures, std::string& messages)
{
  p.search_radius_m = 0.001;
  const Scene scene = ringScene();
  const std::vector<CPose2D> truth = ringPath();
  // The first keyframe of the second visit within 6 m of the start: its
  // cloud sees the start's walls.
  std::size_t snap = 100;
  while (std::hypot(truth[snap].x() - truth[0].x(), truth[snap].y() - truth[0].y()) > 6.0) snap++;
  LoopCloser lc(p, IcpParams{});
  CPose2D est = truth.front(), odo = truth.front();
  double travel = 0;
  const IcpResult reg = goodRegistration();
  closures = 0;
  for (std::size_t k = 0; k < truth.size(); k++)
  {
    if (k > 0)
    {
      const CPose2D rel = truth[k] - truth[k - 1];
      const CPose2D drifted(rel.x(), rel.y(), rel.phi() + mrpt::DEG2RAD(0.04));
      odo = odo + drifted;
      const CPose2D next = k >= snap ? truth[k] : est + drifted;
      travel += std::hypot(next.x() - est.x(), next.y() - est.y());
      est = next;
    }
    const auto ev = lc.addKeyframe(k, est, odo, travel, scene.cloudAt(truth[k]), 0.02,
                                   k > 0 ? &reg : nullptr);
    if (!ev.message.empty()) messages += std::to_string(k) + ": " + ev.message + "\n";
    closures += ev.closed;
  }
  double sum = 0;
  for (std::size_t k = 0; k < snap; k++)
  {
    const auto& a = lc.keyframes()[k].pose;
    sum += std::pow(std::hypot(a.x() - truth[k].x(), a.y() - truth[k].y()), 2);
  }
  return std::sqrt(sum / double(snap));
}
}  // namespace

TEST(LoopClosure, AnImplicitReturnOntoTheOldMapRelaxesTheDriftedStretch)
{
  LoopClosureParams off, on;
  on.chain_recent_m = 12.0;
  std::size_t closures_off = 0, closures_on = 0;
  std::string log_off, log_on;
  const double ate_off = ateBeforeImplicitReturn(off, closures_off, log_off);
  const double ate_on = ateBeforeImplicitReturn(on, closures_on, log_on);
  std::cout << "drifted keyframes before the return: RMS " << ate_off << " m (chain_recent_m 0, "
            << closures_off << " closures), " << ate_on << " m (12 m, " << closures_on
            << " closures)" << std::endl;
  // Off: the return is one registration edge; nothing relaxes the stretch.
  EXPECT_EQ(closures_off, 0u) << log_off;
  EXPECT_GT(ate_off, 0.5);
  // On: the recent pass registers the returning keyframe where the drifted
  // stretch puts it, the metaview's pose joins the old keyframe near the
  // start, and the graph relaxes the stretch.
  EXPECT_GE(closures_on, 1u) << log_on;
  EXPECT_NE(log_on.find("implicit loop with stop"), std::string::npos) << log_on;
  EXPECT_LT(ate_on, ate_off / 5) << log_on;
  EXPECT_LT(ate_on, 0.1) << log_on;
}

TEST(LoopClosure, TheSubmapOfOnePassLeavesADriftedPassOut)
{
  // Pass A along the ring's south corridor, x 1.5 -> 11.5, on the truth
  // (travel 0-10 m); pass B back to x = 7.5 with its estimate 16 cm off
  // along x (travel 10-14 m: never 12 m older than A where it meets it, so
  // no detection). The submap of every old keyframe holds both passes, a
  // double wall 16 cm apart (b17's false closure matched such a submap);
  // the window of A's travel holds A's walls only.
  const Scene scene = ringScene();
  LoopClosureParams p;
  LoopCloser lc(p, IcpParams{});
  const IcpResult reg = goodRegistration();
  std::size_t k = 0;
  double travel = 0;
  for (double x = 1.5; x <= 11.5 + 1e-9; x += 0.5, travel += 0.5)
  {
    const CPose2D truth(x, 1.5, 0.0);
    lc.addKeyframe(k, truth, truth, travel, scene.cloudAt(truth), 0.02, k ? &reg : nullptr);
    k++;
  }
  for (double x = 11.5; x >= 7.5 - 1e-9; x -= 0.5, travel += 0.5)
  {
    const CPose2D truth(x, 1.5, M_PI), drifted(x + 0.16, 1.5, M_PI);
    const auto ev =
        lc.addKeyframe(k, drifted, drifted, travel, scene.cloudAt(truth), 0.02, &reg);
    ASSERT_FALSE(ev.searched) << "stop " << k;
    k++;
  }
  // The share of submap points off every true wall by more than 5 cm.
  const auto offWalls = [&](const mrpt::maps::CSimplePointsMap& m)
  {
    const auto walls = scene.map2d();
    std::size_t off = 0;
    for (std::size_t i = 0; i < m.size(); i++)
    {
      float x, y, z;
      m.getPoint(i, x, y, z);
      off += walls.kdTreeClosestPoint2DsqrError(x, y) > 0.05 * 0.05;
    }
    return double(off) / double(std::max<std::size_t>(1, m.size()));
  };
  voxplore::mapping::Viewpoints views;
  const CPose2D around(9.5, 1.5, 0.0);
  const auto both = lc.submapAround(around, views, 0.0, travel);
  const auto pass_a = lc.submapAround(around, views, 0.0, 10.0);
  std::cout << "points off the walls: both passes " << offWalls(both) << ", pass A "
            << offWalls(pass_a) << std::endl;
  EXPECT_GT(offWalls(both), 0.03);  // the posts and the ends: the walls along x hide the shift
  EXPECT_LT(offWalls(pass_a), 0.01);
  EXPECT_GT(pass_a.size(), 1000u);
}

TEST(LoopClosure, DisabledKeepsTheEstimate)
{
  LoopClosureParams p;
  p.enabled = false;
  LoopCloser lc(p, IcpParams{});
  const auto r = runRing(lc, 0.04, 1.0);
  EXPECT_EQ(r.closures, 0u);
  EXPECT_EQ(r.searched, 0u);
  EXPECT_NEAR(r.ate_after, r.ate_before, 1e-9);
}

TEST(LoopClosure, NoDriftMeansConsistentEdgesAndNoCorrection)
{
  LoopClosureParams p;
  LoopCloser lc(p, IcpParams{});
  const auto r = runRing(lc, 0.0, 1.0);
  EXPECT_EQ(r.closures, 0u);
  EXPECT_GT(r.consistent, 0u);  // the revisit agrees with the graph
  EXPECT_LT(r.ate_after, 1e-6);
}

TEST(LoopClosure, AliasedCorridorGivesNoLoop)
{
  // A corridor whose only features repeat every 1.0 m: a robot coming back
  // with a 0.5 m offset sees the same picture shifted by half a period, so
  // every match is ambiguous (or the corridor degenerate): no closure.
  Scene s;
  s.wall(-2, 0, 40, 0);
  s.wall(-2, 2.5, 40, 2.5);
  for (int i = 0; i < 42; i++)
  {
    s.box(-2 + i * 1.0, 0, 0.1, 0.1);
    s.box(-2 + i * 1.0, 2.4, 0.1, 0.1);
  }
  LoopClosureParams p;
  p.max_window_m = 1.5;
  p.min_window_m = 1.2;
  LoopCloser lc(p, IcpParams{});
  const IcpResult reg = goodRegistration();
  std::vector<CPose2D> truth;
  for (int i = 0; i <= 60; i++) truth.emplace_back(i * 0.5, 1.25, 0.0);
  for (int i = 59; i >= 0; i--) truth.emplace_back(i * 0.5, 1.25, M_PI);
  double travel = 0;
  std::size_t closures = 0, candidates = 0, searched = 0;
  for (std::size_t k = 0; k < truth.size(); k++)
  {
    // The estimate drifts 0.5 m along the corridor on the way back.
    CPose2D est = truth[k];
    if (k > 60) est.x_incr(0.5 * std::min(1.0, double(k - 60) / 20.0));
    if (k > 0) travel += 0.5;
    const auto ev = lc.addKeyframe(k, est, est, travel, s.cloudAt(truth[k]), 0.02, k ? &reg : nullptr);
    closures += ev.closed;
    candidates += ev.candidate;
    searched += ev.searched;
  }
  EXPECT_GT(searched, 10u);
  EXPECT_EQ(closures, 0u) << candidates << " candidates";
}

TEST(LoopClosure, EdgeInformationFollowsTheRegistration)
{
  LoopClosureParams p;
  LoopCloser lc(p, IcpParams{});
  // Odometry only: std grows with the distance.
  const auto near = lc.edgeInformation(nullptr, CPose2D(), 0.5);
  const auto far = lc.edgeInformation(nullptr, CPose2D(), 5.0);
  EXPECT_GT(near(0, 0), far(0, 0));
  // A registration constraining only y (a corridor along x): weak along x,
  // in the frame of a node turned 90 deg that is its local y.
  IcpResult r = goodRegistration();
  r.information = Eigen::Vector3d(1e-3, 1000, 4000).asDiagonal();
  const auto I = lc.edgeInformation(&r, CPose2D(0, 0, M_PI / 2), 0.5);
  EXPECT_NEAR(I(1, 1), 1.0 / (p.edge_max_std_m * p.edge_max_std_m), 1e-6);
  EXPECT_GT(I(0, 0), 1e4);
}

TEST(LoopClosure, BadKeysAreNamed)
{
  mrpt::config::CConfigFileMemory cfg;
  cfg.write("loop_closure", "min_goodness", 1.5);
  LoopClosureParams p;
  try
  {
    voxplore::common::loadChecked(p, cfg, "loop_closure");
    FAIL() << "no error";
  }
  catch (const std::exception& e)
  {
    EXPECT_NE(std::string(e.what()).find("min_goodness"), std::string::npos) << e.what();
  }
  mrpt::config::CConfigFileMemory negative;
  negative.write("loop_closure", "min_points", -1);
  try
  {
    LoopClosureParams fresh;
    voxplore::common::loadChecked(fresh, negative, "loop_closure");
    FAIL() << "no error";
  }
  catch (const std::exception& e)
  {
    EXPECT_NE(std::string(e.what()).find("min_points"), std::string::npos) << e.what();
  }
  mrpt::config::CConfigFileMemory typo;
  typo.write("loop_closure", "min_goodnes", 0.8);
  EXPECT_THROW(voxplore::common::loadChecked(p, typo, "loop_closure"), std::exception);
}

// End to end: a simulated drive round the ring corridor of a generated
// building (seed 2, a 94 m loop), replayed with loop closure on.

TEST(LoopClosure, RingCorridorReplayClosesTheLoopAndCorrectsEveryOutput)
{
  namespace fs = std::filesystem;
  const std::string bin = VOXPLORE_BIN_DIR, dir = voxplore::test::tempPath("loop_ring2");
  fs::remove_all(dir);
  fs::create_directories(dir);
  const auto run = [](const std::string& cmd) { return std::system((cmd + " > /dev/null 2>&1").c_str()); };
  ASSERT_EQ(run(bin + "/voxplore-worldgen --seed 2 --layout ring --out " + dir + "/world"), 0);
  {
    std::ofstream wp(dir + "/loop.txt");  // the ring corridor's centre line, world frame
    wp << "38.35 7.15\n38.35 23.15\n7.15 23.15\n7.15 7.15\n16.0 7.15\n";
  }
  ASSERT_EQ(run(bin + "/mrpt-sim --world " + dir + "/world/building.world --waypoints " + dir +
                "/loop.txt --robot compact --out " + dir + "/sim"),
            0);
  // config/replay.ini with the thesis' registration ([icp] same_side_only
  // false, normal_radius_small_m 0, [metaview] d_dup_2d_m 0): ICP shortens the steps along the
  // corridor (walls slide onto the faces seen from their other side) and
  // the loop has 10 cm to close. Then config/replay.ini as it is, and with
  // [icp] odometry_prior_pairs = 50.
  const auto iniWith = [&](const std::string& name, const std::map<std::string, std::string>& keys)
  {
    std::ifstream in(voxplore::test::sourceDir() + "/config/replay.ini");
    std::ofstream out(dir + "/" + name);
    std::size_t replaced = 0;
    for (std::string line; std::getline(in, line);)
    {
      for (const auto& [k, v] : keys)
        if (line.rfind(k + " ", 0) == 0 || line.rfind(k + "=", 0) == 0)
        {
          line = k + " = " + v;
          replaced++;
        }
      out << line << "\n";
    }
    EXPECT_EQ(replaced, keys.size()) << "config/replay.ini lacks a key of " << name;
  };
  // The OctoMap rebuilt over the stops after a closure, 3 keyframes each,
  // and (whole.ini) all at the closing stop.
  iniWith("thesis.ini", {{"same_side_only", "false"},
                         {"normal_radius_small_m", "0"},
                         {"d_dup_2d_m", "0"},
                         {"octomap_rebuild_per_stop", "3"}});
  iniWith("whole.ini", {{"same_side_only", "false"},
                        {"normal_radius_small_m", "0"},
                        {"d_dup_2d_m", "0"},
                        {"octomap_rebuild_per_stop", "0"}});
  iniWith("prior.ini", {{"odometry_prior_pairs", "50"}});
  ASSERT_EQ(run(bin + "/voxplore-replay --config " + dir + "/thesis.ini --rawlog " + dir +
                "/sim/run.rawlog --out " + dir + "/rep -q"),
            0);
  const auto rows = readCsv(dir + "/rep/stops.csv");
  const auto gt = voxplore::common::readTum(dir + "/sim/trajectory_gt.tum");
  const auto est = voxplore::common::readTum(dir + "/rep/trajectory_est.tum");
  ASSERT_EQ(rows.size(), gt.size());
  ASSERT_EQ(est.size(), gt.size());
  // The map frame is the first ground-truth pose.
  const mrpt::poses::CPose3D T0 = gt.front().pose;
  std::size_t closed = 0;
  for (std::size_t k = 0; k < rows.size(); k++)
  {
    if (rows[k].at("loop_closed") != "1") continue;
    closed++;
    // Not a false loop: the corrected pose of the closing stop is where the
    // robot really was (the drift there was about 10 cm before).
    const mrpt::poses::CPose3D truth = gt[k].pose - T0;
    const double err = std::hypot(std::stod(rows[k].at("x")) - truth.x(),
                                  std::stod(rows[k].at("y")) - truth.y());
    EXPECT_LT(err, 0.05) << "stop " << k;
    EXPECT_GT(std::stod(rows[k].at("loop_correction_m")), 0.03);
    EXPECT_GT(std::stod(rows[k].at("graph_shift_max_m")), 0.0);
  }
  EXPECT_GE(closed, 1u);
  // trajectory_est.tum, stops.csv and the simplemap's keyframes agree (all corrected).
  mrpt::maps::CSimpleMap sm = voxplore::test::loadSimplemap(dir + "/rep/map.simplemap");
  std::size_t kf = 0;
  for (std::size_t k = 0; k < rows.size(); k++)
  {
    EXPECT_NEAR(est[k].pose.x(), std::stod(rows[k].at("x")), 1e-4);
    if (rows[k].at("integrated") != "1") continue;
    ASSERT_LT(kf, sm.size());
    mrpt::poses::CPose3DPDF::Ptr pdf;
    mrpt::obs::CSensoryFrame::Ptr sf;
    sm.get(kf++, pdf, sf);
    EXPECT_NEAR(pdf->getMeanVal().x(), std::stod(rows[k].at("x")), 1e-4) << "stop " << k;
    EXPECT_NEAR(pdf->getMeanVal().y(), std::stod(rows[k].at("y")), 1e-4) << "stop " << k;
  }
  EXPECT_EQ(kf, sm.size());
  // trajectory_online.tum keeps each stop's estimate as the robot left it:
  // the relaxation moved the stops before the first closure, not the last stop.
  const auto online = voxplore::common::readTum(dir + "/rep/trajectory_online.tum");
  ASSERT_EQ(online.size(), est.size());
  std::size_t first_closed = 0;
  while (first_closed < rows.size() && rows[first_closed].at("loop_closed") != "1") first_closed++;
  double moved = 0;
  for (std::size_t k = 0; k < first_closed; k++)
    moved = std::max(moved, online[k].pose.distanceTo(est[k].pose));
  EXPECT_GT(moved, 0.01);
  EXPECT_NEAR(online.back().pose.distanceTo(est.back().pose), 0.0, 1e-4);
  std::ifstream js(dir + "/rep/summary.json");
  const std::string summary((std::istreambuf_iterator<char>(js)), std::istreambuf_iterator<char>());
  EXPECT_NE(summary.find("\"loop_closures\": " + std::to_string(closed)), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"ate_online_rmse_m\": "), std::string::npos) << summary;
  EXPECT_EQ(run("bt2vrml " + dir + "/rep/map.bt"), 0);

  // The OctoMap rebuild spread over the stops: 3 keyframes at the closing
  // stop and at each one after it, until none is left; the map written at
  // the end is the one rebuilt at once (same keyframes, poses and order:
  // byte for byte), and the trajectory is the same (ICP uses the metaview).
  std::size_t spread_stops = 0;
  for (std::size_t k = 0; k < rows.size(); k++)
  {
    if (rows[k].at("maps_rebuilt") != "1") continue;
    EXPECT_EQ(rows[k].at("octomap_rebuilt_keyframes"), "3") << "stop " << k;
    std::size_t left = std::stoul(rows[k].at("octomap_rebuild_left"));
    EXPECT_GT(left, 10u) << "stop " << k;
    for (std::size_t j = k + 1; j < rows.size() && left > 0 && rows[j].at("maps_rebuilt") != "1"; j++)
    {
      // an integrated stop is one more keyframe to take; 3 are taken
      const std::size_t todo = left + (rows[j].at("integrated") == "1" ? 1u : 0u);
      const std::size_t now = std::stoul(rows[j].at("octomap_rebuild_left"));
      EXPECT_EQ(std::stoul(rows[j].at("octomap_rebuilt_keyframes")), std::min<std::size_t>(3, todo))
          << "stop " << j;
      EXPECT_EQ(now, todo > 3 ? todo - 3 : 0) << "stop " << j;
      left = now;
      spread_stops++;
    }
  }
  EXPECT_GT(spread_stops, 5u);
  ASSERT_EQ(run(bin + "/voxplore-replay --config " + dir + "/whole.ini --rawlog " + dir +
                "/sim/run.rawlog --out " + dir + "/rep_whole -q"),
            0);
  const auto bytes = [](const std::string& path)
  {
    std::ifstream f(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  };
  EXPECT_EQ(bytes(dir + "/rep/trajectory_est.tum"), bytes(dir + "/rep_whole/trajectory_est.tum"));
  const std::string bt = bytes(dir + "/rep/map.bt");
  EXPECT_GT(bt.size(), 1000u);
  EXPECT_TRUE(bt == bytes(dir + "/rep_whole/map.bt")) << "the spread rebuild wrote another OctoMap";
  for (const auto& row : readCsv(dir + "/rep_whole/stops.csv"))
    EXPECT_EQ(row.at("octomap_rebuild_left"), "0");

  // Today's registration (config/replay.ini as it is), and with the
  // odometry prior: the whole loop within a few cm of the truth (measured
  // ATE 0.036 and 0.033 m; 0.138 m with the thesis' registration above).
  const auto ateOf = [&](const std::string& config, const std::string& out)
  {
    EXPECT_EQ(run(bin + "/voxplore-replay --config " + config + " --rawlog " + dir +
                  "/sim/run.rawlog --out " + dir + "/" + out + " -q"),
              0);
    const auto e = voxplore::common::readTum(dir + "/" + out + "/trajectory_est.tum");
    EXPECT_EQ(e.size(), gt.size());
    double sum2 = 0, worst = 0;
    for (std::size_t k = 0; k < std::min(e.size(), gt.size()); k++)
    {
      const mrpt::poses::CPose3D truth = gt[k].pose - T0;
      const double err = std::hypot(e[k].pose.x() - truth.x(), e[k].pose.y() - truth.y());
      sum2 += err * err;
      worst = std::max(worst, err);
    }
    const double ate = std::sqrt(sum2 / static_cast<double>(std::max<std::size_t>(1, gt.size())));
    std::cout << "ring replay " << out << ": ATE " << ate << " m, max " << worst << " m" << std::endl;
    return std::pair{ate, worst};
  };
  const auto [ate, worst] = ateOf(voxplore::test::sourceDir() + "/config/replay.ini", "rep_default");
  EXPECT_LT(ate, 0.05);
  EXPECT_LT(worst, 0.10);
  // No false loop: whatever closed, the closing stop is where the robot was.
  for (const auto& row : readCsv(dir + "/rep_default/stops.csv"))
    if (row.at("loop_closed") == "1")
    {
      const std::size_t k = std::stoul(row.at("stop"));
      const mrpt::poses::CPose3D truth = gt.at(k).pose - T0;
      EXPECT_LT(std::hypot(std::stod(row.at("x")) - truth.x(), std::stod(row.at("y")) - truth.y()), 0.05)
          << "stop " << k;
    }
  const auto [ate_prior, worst_prior] = ateOf(dir + "/prior.ini", "rep_prior");
  EXPECT_LT(ate_prior, 0.04);
  EXPECT_LT(worst_prior, 0.10);
}

namespace
{
/// Two old passes along the ring's south corridor from its west end: A on
/// the truth (x 1.5 -> 8, 0.5 m apart) seeing 2.5 m, then B (x 1.5 -> 16.5,
/// 1 m apart) seeing 6 m with its estimate 16 cm off along x; then the
/// robot back at x = 2 -> 6 on the truth, its estimate 8 cm off. The submap
/// of every old keyframe holds both passes, B's reaching further. Returns,
/// for every match taken (candidate, closure or consistent edge), the loop
/// edge's error: the matched pose relative to the keyframe it is joined to
/// (as it stood when matched), against the true relative pose.
std::vector<double> twoPassEdgeErrors(const LoopClosureParams& p, std::string& messages)
{
  const Scene scene = ringScene();
  LoopCloser lc(p, IcpParams{});
  const IcpResult reg = goodRegistration();
  std::vector<CPose2D> truth;
  double travel = 0;
  const auto add = [&](const CPose2D& t, const CPose2D& est, double range_m)
  {
    const std::size_t k = truth.size();
    truth.push_back(t);
    return lc.addKeyframe(k, est, est, travel, scene.cloudAt(t, range_m), 0.02, k ? &reg : nullptr);
  };
  for (double x = 1.5; x <= 8.0 + 1e-9; x += 0.5, travel += 0.5)
    add(CPose2D(x, 1.5, 0), CPose2D(x, 1.5, 0), 2.5);
  travel += 14.0;  // out of the corridor and back: A is old for B
  for (double x = 1.5; x <= 16.5 + 1e-9; x += 1.0, travel += 1.0)
    add(CPose2D(x, 1.5, 0), CPose2D(x + 0.16, 1.5, 0), 6.0);
  travel += 20.0;
  std::vector<double> errors;
  for (double x = 2.0; x <= 6.0 + 1e-9; x += 0.5, travel += 0.5)
  {
    std::vector<CPose2D> before;  // a closure relaxes the graph after the match
    for (const auto& kf : lc.keyframes()) before.push_back(kf.pose);
    const CPose2D t(x, 1.5, 0);
    const auto ev = add(t, CPose2D(x + 0.08, 1.45, mrpt::DEG2RAD(1.0)), 6.0);
    if (!ev.message.empty()) messages += ev.message + "\n";
    if (!(ev.candidate || ev.closed || ev.consistent)) continue;
    const std::size_t j = ev.with_stop;  // the stops are the keyframe indices
    const CPose2D err = (ev.matched - before[j]) - (t - truth[j]);
    errors.push_back(std::hypot(err.x(), err.y()));
  }
  return errors;
}
}  // namespace

TEST(LoopClosure, AMatchMustHoldAgainstItsAnchorsOwnPass)
{
  // Off: the match follows pass B, which reaches further, and is joined to
  // the nearest old keyframe, one of A's: its edge is 16-21 cm off (and
  // confirmed by the next such match).
  std::string msg_off, msg_on;
  LoopClosureParams p;
  p.anchor_check_m = 0;
  const auto off = twoPassEdgeErrors(p, msg_off);
  const auto on = twoPassEdgeErrors(LoopClosureParams{}, msg_on);  // on by default
  std::cout << "off:\n" << msg_off << "on:\n" << msg_on << std::endl;
  ASSERT_FALSE(off.empty());
  EXPECT_GT(*std::max_element(off.begin(), off.end()), 0.12);
  // On (0.05 m): A's own pass moves those matches 16 cm, they are dropped; the ones
  // joined to B's keyframes stay and close the loop.
  ASSERT_GE(on.size(), 2u);
  EXPECT_LT(*std::max_element(on.begin(), on.end()), 0.03);
  EXPECT_NE(msg_on.find("own pass moves the match"), std::string::npos);
  EXPECT_NE(msg_on.find("loop closed"), std::string::npos);
  // A pass that pairs less than anchor_min_goodness of the cloud does not
  // judge: A's short-sighted pass pairs 0.62-0.74, so at 0.8 nothing is
  // refused and the 16 cm edges are back.
  std::string msg_blind;
  p.anchor_check_m = 0.05;
  p.anchor_min_goodness = 0.8;
  const auto blind = twoPassEdgeErrors(p, msg_blind);
  ASSERT_FALSE(blind.empty());
  EXPECT_GT(*std::max_element(blind.begin(), blind.end()), 0.12);
  EXPECT_EQ(msg_blind.find("own pass moves the match"), std::string::npos);
}

TEST(LoopClosure, AMatchThatSlidesAlongACorridorIsFoundByTheProbe)
{
  // A corridor along x whose only cross features are a few fins: the scene
  // fixes y well and x weakly (information ratio under probe_ratio). The
  // submap of a right pass holds each fin once; one with a drifted pass
  // too holds every fin twice, 0.2 m apart (b3 compact nearest seed 3: the
  // stops of a stretch mapped 0.12 m off along a hall's long wall), and
  // there ICP ends wherever it starts along x.
  Scene right;
  right.wall(-2, 0, 30, 0);
  right.wall(-2, 2.5, 30, 2.5);
  const std::vector<double> fins = {3.1, 5.6, 8.7, 11.1, 13.4, 15.9, 17.9};
  for (const double x : fins) right.box(x, 0, 0.4, 0.6);
  Scene twice = right;
  for (const double x : fins) twice.box(x + 0.2, 0, 0.4, 0.6);
  const CPose2D truth(10.0, 1.25, 0.0);
  const auto cloud = right.cloudAt(truth);
  IcpParams p;
  p.max_correction_xy_m = 0.6;
  const CPose2D estimate(10.12, 1.25, 0.0);  // the drifted estimate
  LoopClosureParams lcp;
  lcp.probe_ratio = 0.3;  // off by default; the value measured in BENCHMARKS.md
  for (const bool drifted_pass : {false, true})
  {
    const auto submap = (drifted_pass ? twice : right).map2d();
    const IcpResult m = voxplore::mapping::alignPlanar(submap, cloud, estimate, p);
    ASSERT_TRUE(m.accepted) << m.reason;
    EXPECT_GT(m.info_ratio, p.degeneracy_ratio) << "not degenerate";
    EXPECT_LT(m.info_ratio, lcp.probe_ratio) << "weak along x: probed";
    const double slide = voxplore::mapping::slideAlongWeak(submap, nullptr, cloud, estimate, m, p, lcp.probe_m);
    std::cout << (drifted_pass ? "fins twice" : "fins once") << ": match " << m.pose.x() - truth.x()
              << " m off along x, ratio " << m.info_ratio << ", probes end up to " << slide
              << " m from it" << std::endl;
    if (drifted_pass)
      EXPECT_GT(slide, lcp.probe_tol_m);
    else
    {
      EXPECT_LT(std::abs(m.pose.x() - truth.x()), 0.01);
      EXPECT_LE(slide, lcp.probe_tol_m);
    }
  }
}

// [loop_closure] min_points: a stop whose cloud has fewer points searches no
// loop (willowgarage's open space: a loop closed 0.29-0.36 m off from stops
// of 1,016-1,342 points). The ring's stops, all under the limit, close
// nothing; at a limit under all of them the ring closes as before.
TEST(LoopClosure, AStopWithASparseCloudSearchesNoLoop)
{
  const Scene scene = ringScene();
  std::size_t fewest = std::numeric_limits<std::size_t>::max(), most = 0;
  for (const CPose2D& t : ringPath())
  {
    const std::size_t n = scene.cloudAt(t).size();
    fewest = std::min(fewest, n);
    most = std::max(most, n);
  }
  ASSERT_GT(fewest, 0u);

  LoopClosureParams sparse;
  sparse.min_points = static_cast<int>(most) + 1;
  LoopCloser lc_sparse(sparse, IcpParams{});
  const auto r = runRing(lc_sparse, 0.04, 1.0);
  EXPECT_EQ(r.searched, 0u);
  EXPECT_EQ(r.closures, 0u);
  EXPECT_GT(r.ate_after, 0.5) << "the drift stays";

  LoopClosureParams dense;
  dense.min_points = static_cast<int>(fewest);
  LoopCloser lc_dense(dense, IcpParams{});
  const auto d = runRing(lc_dense, 0.04, 1.0);
  EXPECT_GT(d.searched, 0u);
  EXPECT_GE(d.closures, 1u);
  EXPECT_LT(d.ate_after, 0.1);
}
