/* voxplore — MRPT's reactive navigator as StopAndScanDriver holds it
 * (StopAndScanDriver.cpp builds it, StopAndScanDriver_reactive.cpp drives
 * it). Internal to libs/navigation. */
#pragma once

#include <mrpt/nav/reactive/CReactiveNavigationSystem.h>
#include <voxplore/navigation/StopAndScanDriver.h>

#include <string>

#include "RobotNavAdapter.h"

namespace voxplore::navigation
{
namespace detail
{
// CReactiveNavigationSystem whose delay statistics (CAbstractNavigator's
// always-enabled m_timlog_delays) are not dumped to the console on destruction.
class QuietReactiveNavigator : public mrpt::nav::CReactiveNavigationSystem
{
 public:
  QuietReactiveNavigator(mrpt::nav::CRobot2NavInterface& robot, bool verbose)
      : CReactiveNavigationSystem(robot, verbose /*console output*/, false /*no log files*/)
  {
    m_timlog_delays.enable(verbose);
  }

  /// Opens the next free DIR/log_NNN.reactivenavlog (MRPT's naming).
  /// @return false when MRPT could not open it (it only logs the error).
  bool openNavlog(const std::string& dir)
  {
    setLogFileDirectory(dir);
    // MRPT writes the PTG descriptions (what navlog-viewer needs to draw the
    // paths) at the start of a file only when the stream pointer differs
    // from the previous file's: a new file may reuse the freed address.
    m_prev_logfile = nullptr;
    enableLogFile(true);
    return m_logFile != nullptr;
  }
  /// Closes (and so finishes the gzip stream of) the current log file.
  void closeNavlog() { enableLogFile(false); }
};
}  // namespace detail

struct StopAndScanDriver::Impl
{
  RobotNavAdapter adapter;
  detail::QuietReactiveNavigator nav;

  Impl(RobotInterface& robot, bool verbose) : adapter(robot), nav(adapter, verbose) {}
};
}  // namespace voxplore::navigation
