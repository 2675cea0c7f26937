# Sanitizer and fuzzing builds (CI stages 2 and 3, scripts/sanitize.sh and
# scripts/fuzz.sh). Included from the top-level CMakeLists.txt before any
# target is created, so the flags reach every voxplore library, app and test.
# MRPT, OctoMap, Embree and assimp are system libraries and stay uninstrumented.
#
# VOXPLORE_SANITIZE=ON  AddressSanitizer + UndefinedBehaviorSanitizer (gcc or
#                       clang), -O1 -g; build with an empty CMAKE_BUILD_TYPE so
#                       assert()/Eigen range checks stay on. Run the tests with
#                       ASAN_OPTIONS/UBSAN_OPTIONS/LSAN_OPTIONS as in
#                       scripts/sanitize.sh.
# VOXPLORE_FUZZ=ON      libFuzzer targets in fuzz/ (clang only): libraries get
#                       -fsanitize=fuzzer-no-link,address,undefined, the fuzz
#                       executables -fsanitize=fuzzer,address,undefined.

option(VOXPLORE_SANITIZE "Build everything with AddressSanitizer + UndefinedBehaviorSanitizer" OFF)
option(VOXPLORE_FUZZ "Build the libFuzzer targets in fuzz/ (clang, ASan + UBSan)" OFF)

if(VOXPLORE_SANITIZE AND VOXPLORE_FUZZ)
  message(FATAL_ERROR "VOXPLORE_SANITIZE and VOXPLORE_FUZZ are separate builds: enable one")
endif()

set(VOXPLORE_SANITIZER_FLAGS
  -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -O1 -g)

if(VOXPLORE_SANITIZE)
  message(STATUS "voxplore: ASan + UBSan build (${VOXPLORE_SANITIZER_FLAGS})")
  add_compile_options(${VOXPLORE_SANITIZER_FLAGS})
  add_link_options(-fsanitize=address,undefined)
endif()

if(VOXPLORE_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "VOXPLORE_FUZZ needs clang (libFuzzer): configure with "
                        "-DCMAKE_CXX_COMPILER=clang++-14")
  endif()
  message(STATUS "voxplore: libFuzzer build (fuzzer-no-link + ASan + UBSan for the libraries)")
  add_compile_options(-fsanitize=fuzzer-no-link ${VOXPLORE_SANITIZER_FLAGS})
  add_link_options(-fsanitize=address,undefined)
endif()
