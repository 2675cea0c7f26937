/* voxplore — how the apps keep freed memory for the next planning step. */
#pragma once

namespace voxplore::common
{
/// @brief Keeps memory the process frees in its heap for reuse instead of
///        handing it back to the kernel: glibc's mmap threshold raised to
///        32 MB (fixed, not the dynamic one) and its trim threshold to 256 MB.
///        Every planning step allocates its grids afresh (the footprint
///        space alone is five 8-byte layers, 2 MB each on a 500 m^2 map at
///        5 cm); returned to the kernel at the end of a step, each of their
///        pages faults again at the next, which on this project's machines
///        (a paravirtualised VM) was half the footprint space's time
///        (bench_footprint, b10 map: 54.9 -> 19.8 ms). The apps call it first
///        (apps::runGuarded); a program embedding the planner may too.
///        Does nothing on a C library other than glibc.
void keepFreedMemoryForReuse();
}  // namespace voxplore::common
