// The command line of the map benchmarks (bench_footprint, bench_tour):
// --map=<file.bt>, --pose=x,y,yaw_deg, optionally --config=<ini>; the rest
// goes to Google Benchmark.
#pragma once

#include <cstdio>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

namespace voxplore::bench
{
struct MapArgs
{
  std::string map, config;
  double x = 0, y = 0, yaw_deg = 0;
  std::vector<char*> rest;  ///< argv[0] and the arguments not ours
};

/// @return false (after a message naming `tool`) on a malformed --pose or no --map
inline bool parseMapArgs(int argc, char** argv, const char* tool, MapArgs& out)
{
  for (int i = 0; i < argc; ++i)
  {
    if (std::strncmp(argv[i], "--map=", 6) == 0)
      out.map = argv[i] + 6;
    else if (std::strncmp(argv[i], "--config=", 9) == 0)
      out.config = argv[i] + 9;
    else if (std::strncmp(argv[i], "--pose=", 7) == 0)
    {
      if (std::sscanf(argv[i] + 7, "%lf,%lf,%lf", &out.x, &out.y, &out.yaw_deg) != 3)
      {
        std::cerr << tool << ": --pose=x,y,yaw_deg expected, got '" << argv[i] + 7 << "'\n";
        return false;
      }
    }
    else
      out.rest.push_back(argv[i]);
  }
  if (out.map.empty())
  {
    std::cerr << tool << ": --map=<map.bt> is required (a voxplore-explore run's map.bt of a "
                 "generated building) and --pose=x,y,yaw_deg inside it\n";
    return false;
  }
  return true;
}
}  // namespace voxplore::bench
