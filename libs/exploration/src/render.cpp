// PNG of the exploration grid with its layers, in the thesis' colours (fig. 4.12).
#include <mrpt/img/CImage.h>
#include <voxplore/exploration/Planner.h>

#include <stdexcept>

namespace voxplore::exploration
{
namespace
{
using mrpt::img::TColor;

const TColor kFree(255, 255, 255), kOccupied(0, 0, 0), kUnknown(220, 40, 40),
    kCollision(150, 150, 150), kMaybe(60, 190, 60), kReachable(120, 160, 255),
    kFrontier(0, 220, 220), kChosen(255, 230, 0), kSampleSpace(170, 90, 200),
    kSample(255, 150, 0), kPath(230, 0, 200), kRobot(140, 0, 0), kTrail(120, 30, 30),
    kTour(0, 140, 0), kRetired(130, 70, 30);

class Canvas
{
 public:
  Canvas(const Grid<SpaceState>& g, int scale)
      : g_(g), scale_(scale), img_(g.getSizeX() * scale, g.getSizeY() * scale, mrpt::img::CH_RGB)
  {
  }
  void cell(const Cell& c, const TColor& col)
  {
    const int x0 = c.cx * scale_, y0 = (static_cast<int>(g_.getSizeY()) - 1 - c.cy) * scale_;
    img_.filledRectangle(x0, y0, x0 + scale_ - 1, y0 + scale_ - 1, col);
  }
  void pixelOf(const Eigen::Vector2d& p, int& x, int& y) const
  {
    x = static_cast<int>((p.x() - g_.getXMin()) / g_.getResolution() * scale_);
    y = static_cast<int>((g_.getYMax() - p.y()) / g_.getResolution() * scale_);
  }
  void line(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const TColor& col, int width = 1)
  {
    int x0, y0, x1, y1;
    pixelOf(a, x0, y0);
    pixelOf(b, x1, y1);
    img_.line(x0, y0, x1, y1, col, width);
  }
  void dot(const Eigen::Vector2d& p, int radius, const TColor& col)
  {
    int x, y;
    pixelOf(p, x, y);
    img_.drawCircle(x, y, radius, col, 2);
  }
  void pose(const mrpt::poses::CPose2D& q, const TColor& col)
  {
    const Eigen::Vector2d p(q.x(), q.y());
    dot(p, 2 * scale_, col);
    line(p, p + 0.5 * Eigen::Vector2d(std::cos(q.phi()), std::sin(q.phi())), col, 2);
  }
  void save(const std::string& path)
  {
    if (!img_.saveToFile(path)) throw std::runtime_error("cannot write image '" + path + "'");
  }

 private:
  const Grid<SpaceState>& g_;
  int scale_;
  mrpt::img::CImage img_;
};

/// Reachable free cells of a room: one of eight blues and greens by the
/// room's index (neighbouring rooms usually differ), darker for the robot's.
TColor roomColour(int32_t room, bool robots)
{
  static const TColor palette[8] = {{120, 160, 255}, {150, 210, 240}, {140, 220, 190},
                                    {180, 180, 250}, {110, 190, 220}, {170, 230, 170},
                                    {130, 140, 230}, {190, 210, 255}};
  const TColor c = palette[static_cast<std::size_t>(room) % 8];
  if (!robots) return c;
  return TColor(static_cast<uint8_t>(c.R * 0.75), static_cast<uint8_t>(c.G * 0.75),
                static_cast<uint8_t>(c.B * 0.75));
}

TColor spaceColour(SpaceState s)
{
  switch (s)
  {
    case SpaceState::Unknown:
      return kUnknown;
    case SpaceState::Occupied:
      return kOccupied;
    case SpaceState::Collision:
      return kCollision;
    case SpaceState::MaybeCollision:
      return kMaybe;
    case SpaceState::Free:
      return kFree;
  }
  return kUnknown;
}
}  // namespace

void renderPlan(
    const PlanResult& r, const mrpt::poses::CPose2D& robot, const std::string& png_path,
    const std::vector<mrpt::poses::CPose2D>& trajectory, int scale)
{
  if (!r.space) throw std::runtime_error("renderPlan: the plan holds no grid layers");
  const auto& st = r.space->state;
  Canvas cv(st, std::max(1, scale));
  for (int cy = 0; cy < static_cast<int>(st.getSizeY()); cy++)
    for (int cx = 0; cx < static_cast<int>(st.getSizeX()); cx++)
    {
      const SpaceState s = *st.cellByIndex(cx, cy);
      const bool reach = r.frontiers && *r.frontiers->reachable.cellByIndex(cx, cy);
      const int32_t room = r.rooms ? r.rooms->roomAt({cx, cy}) : -1;
      const std::size_t i = static_cast<std::size_t>(cx) + static_cast<std::size_t>(cy) * st.getSizeX();
      const bool retired = s == SpaceState::Unknown && i < r.retired.size() && r.retired[i];
      cv.cell({cx, cy}, reach && s == SpaceState::Free
                            ? (room >= 0 ? roomColour(room, room == r.robot_room) : kReachable)
                            : retired ? kRetired : spaceColour(s));
    }
  for (const auto& c : r.sample_space) cv.cell(c, kSampleSpace);
  if (r.frontiers)
    for (const auto& f : r.frontiers->frontiers)
      for (const auto& c : f.cells) cv.cell(c, kFrontier);
  if (r.frontier)
    for (const auto& c : r.frontier->cells) cv.cell(c, kChosen);
  for (std::size_t i = 1; i < trajectory.size(); i++)
    cv.line({trajectory[i - 1].x(), trajectory[i - 1].y()}, {trajectory[i].x(), trajectory[i].y()},
            kTrail, 2);
  if (r.frontiers && !r.tour.order.empty())
  {
    // The tour: robot, then each frontier's centre in order.
    Eigen::Vector2d from(robot.x(), robot.y());
    for (const std::size_t i : r.tour.order)
    {
      const Eigen::Vector2d to = r.frontiers->frontiers[i].center;
      cv.line(from, to, kTour, 1);
      from = to;
    }
  }
  for (const auto& s : r.samples) cv.dot({s.x(), s.y()}, scale, kSample);
  if (r.path)
  {
    const auto& w = r.path->waypoints;
    for (std::size_t i = 1; i < w.size(); i++) cv.line(w[i - 1], w[i], kPath, 2);
    for (const auto& p : w) cv.dot(p, scale / 2 + 1, kPath);
  }
  if (r.ok()) cv.pose(r.target, kPath);
  cv.pose(robot, kRobot);
  cv.save(png_path);
}

}  // namespace voxplore::exploration
