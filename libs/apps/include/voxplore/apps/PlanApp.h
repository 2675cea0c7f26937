/* voxplore — the voxplore-plan application: one planning step of a run,
 * planned again from its saved inputs. */
#pragma once

#include <voxplore/exploration/Planner.h>

#include <array>
#include <string>
#include <vector>

namespace voxplore::apps
{
/// @brief Command-line options of voxplore-plan.
struct PlanOptions
{
  std::string inputs;  ///< plans/step_NNN.txt of a run ([explore] keep_plan_inputs)
  std::string config;  ///< the run's params.ini (the planner's sections in force)
  std::string png;     ///< the step image (renderPlan); empty: none
  int scale = 4;       ///< pixels per cell of the image
  bool ignore_blacklist = false;  ///< plan as if no target had been given up
  bool ignore_sensed = false;     ///< ... and without the driver's sensed points
  /// Print the grid round these points (x, y [m], yaw [deg]): G's states, the
  /// collision space's, and, with the footprint model, which states of the
  /// yaw's bin are clear of occupied cells, of open unknown, turnable and
  /// reached (why the robot does or does not get through a door).
  std::vector<std::array<double, 3>> probes;
  int probe_radius = 12;  ///< cells each side of a probe
  /// Plan the step this many times in one process and print each stage's
  /// median and minimum [ms] (the first plan is the one reported; the
  /// explorer plans in a warm process, a single run pays the first touch of
  /// every grid).
  int repeat = 1;
};

/// @brief voxplore-plan: reads a planning step's inputs and the planner's
///        parameters, plans, and reports every stage (frontiers with their
///        length, opening, travel distance and room; why each was skipped;
///        the known floor cut off; the target and its path; the timings).
class PlanApp
{
 public:
  /// @brief Parses the command line (TCLAP, --help) and runs. Never throws.
  int run(int argc, const char* const* argv);
  /// @brief Plans with parsed options and prints the report to `out`.
  /// @throws std::runtime_error naming the file (and line or key) on bad input.
  exploration::PlanResult execute(const PlanOptions& opts, std::ostream& out);
};

}  // namespace voxplore::apps
