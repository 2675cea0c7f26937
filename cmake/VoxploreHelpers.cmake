# voxplore_add_library(<name> SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# Creates target voxplore_<name> with alias voxplore::<name>, headers under
# libs/<name>/include/voxplore/<name>/, installed and exported.
function(voxplore_add_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  set(tgt voxplore_${name})
  add_library(${tgt} ${ARG_SOURCES})
  add_library(voxplore::${name} ALIAS ${tgt})
  set_target_properties(${tgt} PROPERTIES EXPORT_NAME ${name} OUTPUT_NAME voxplore_${name})
  target_compile_features(${tgt} PUBLIC cxx_std_17)
  target_include_directories(${tgt} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(${tgt} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  voxplore_set_warnings(${tgt})
  install(TARGETS ${tgt} EXPORT voxploreTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  install(DIRECTORY include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()

function(voxplore_set_warnings tgt)
  target_compile_options(${tgt} PRIVATE -Wall -Wextra -Wpedantic)
  if(VOXPLORE_WERROR)
    target_compile_options(${tgt} PRIVATE -Werror)
  endif()
endfunction()

# voxplore_add_app(<exe-name> <main.cpp>): thin main over voxplore::apps.
function(voxplore_add_app name src)
  add_executable(${name} ${src})
  target_link_libraries(${name} PRIVATE voxplore::apps)
  voxplore_set_warnings(${name})
  install(TARGETS ${name} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endfunction()
