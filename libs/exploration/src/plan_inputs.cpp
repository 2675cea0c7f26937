/* voxplore — planning-step inputs on disk (see plan_inputs.h). */
#include <octomap/OcTree.h>
#include <voxplore/exploration/plan_inputs.h>

#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace voxplore::exploration
{
void writePlanInputs(const std::string& path, const PlanInputs& in, const octomap::OcTree& V)
{
  std::ofstream f(path);
  f << std::setprecision(std::numeric_limits<double>::max_digits10);
  f << "# voxplore planning-step inputs (map frame, m, rad); the map is " << path << ".ot\n";
  f << "robot " << in.robot.x() << " " << in.robot.y() << " " << in.robot.phi() << "\n";
  f << "step " << in.step << "\n";
  for (const auto& p : in.blacklist) f << "bl " << p.x() << " " << p.y() << "\n";
  for (const auto& p : in.sensed_obstacles) f << "so " << p.x() << " " << p.y() << "\n";
  for (const auto& p : in.low_obstacles) f << "lo " << p.x() << " " << p.y() << "\n";
  for (const auto& p : in.approach) f << "ap " << p.x() << " " << p.y() << "\n";
  for (const auto& q : in.swept) f << "sw " << q.x() << " " << q.y() << " " << q.z() << "\n";
  for (const auto& p : in.region) f << "rg " << p.x() << " " << p.y() << "\n";
  if (in.looks)
  {
    for (const auto& l : in.looks->records())
      f << "lk " << l.kx << " " << l.ky << " " << l.n << " " << l.x << " " << l.y << "\n";
    for (const auto& q : in.looks->pending())
      f << "ls " << q.x() << " " << q.y() << " " << q.phi() << "\n";
  }
  f.flush();
  if (!f) throw std::runtime_error("cannot write '" + path + "'");
  if (!V.write(path + ".ot")) throw std::runtime_error("cannot write '" + path + ".ot'");
}

PlanInputs readPlanInputs(const std::string& path, std::unique_ptr<octomap::OcTree>& V_out)
{
  std::ifstream f(path);
  if (!f) throw std::runtime_error("cannot read planning-step inputs '" + path + "'");
  PlanInputs in;
  auto looks = std::make_shared<FrontierLooks>();
  bool has_looks = false;
  bool has_robot = false;
  std::string line;
  for (int n = 1; std::getline(f, line); ++n)
  {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    const auto bad = [&](const std::string& why)
    { return std::runtime_error(path + ":" + std::to_string(n) + ": " + why + ": '" + line + "'"); };
    double a = 0, b = 0, c = 0;
    if (tag == "robot" || tag == "sw")
    {
      if (!(ls >> a >> b >> c)) throw bad("expected three numbers after '" + tag + "'");
      if (tag == "robot")
      {
        in.robot = mrpt::poses::CPose2D(a, b, c);
        has_robot = true;
      }
      else
        in.swept.emplace_back(a, b, c);
    }
    else if (tag == "bl" || tag == "so" || tag == "lo" || tag == "ap" || tag == "rg")
    {
      if (!(ls >> a >> b)) throw bad("expected two numbers after '" + tag + "'");
      (tag == "bl"   ? in.blacklist
       : tag == "so" ? in.sensed_obstacles
       : tag == "lo" ? in.low_obstacles
       : tag == "ap" ? in.approach
                     : in.region)
          .emplace_back(a, b);
    }
    else if (tag == "lk")
    {
      FrontierLooks::Look l;
      if (!(ls >> l.kx >> l.ky >> l.n >> l.x >> l.y) || l.n == 0)
        throw bad("expected 'lk kx ky n x y' with n >= 1");
      looks->restore(l);
      has_looks = true;
    }
    else if (tag == "ls")
    {
      if (!(ls >> a >> b >> c)) throw bad("expected three numbers after 'ls'");
      looks->addStop(mrpt::poses::CPose2D(a, b, c));
      has_looks = true;
    }
    else if (tag == "step")
    {
      if (!(ls >> in.step)) throw bad("expected a step number");
    }
    else
      throw bad("unknown tag '" + tag + "' (expected robot, step, bl, so, lo, ap, sw, rg, lk or ls)");
    std::string rest;
    if (ls >> rest) throw bad("trailing '" + rest + "'");
  }
  if (!has_robot) throw std::runtime_error(path + ": no 'robot x y yaw' line");
  if (has_looks) in.looks = std::move(looks);
  std::unique_ptr<octomap::AbstractOcTree> t(octomap::AbstractOcTree::read(path + ".ot"));
  auto* tree = dynamic_cast<octomap::OcTree*>(t.get());
  if (!tree) throw std::runtime_error("cannot read the map '" + path + ".ot' (an OctoMap OcTree .ot)");
  t.release();
  V_out.reset(tree);
  return in;
}

}  // namespace voxplore::exploration
