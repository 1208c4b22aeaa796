# mapnav_module(NAME
#   [INTERFACE]                      header-only / stub module
#   SOURCES a.cpp ...                implementation files (src/)
#   PUBLIC_DEPS   targets ...        needed by users of the public headers
#   PRIVATE_DEPS  targets ...        used only inside the .cpp files (CGAL, OpenCV, Boost.Graph go here)
# )
# Creates target mapnav_NAME with alias mapnav::NAME, public headers in NAME/include/mapnav/NAME/,
# installs and exports it.
set(MAPNAV_WARNINGS -Wall -Wextra -Wpedantic)
if(CMAKE_UNITY_BUILD)
  # In a unity file a .cpp is an included file, and GCC then takes its Impl structs holding types of
  # the .cpp's anonymous namespace (map.cpp, predict.cpp, route.cpp) for header types that do.
  list(APPEND MAPNAV_WARNINGS -Wno-subobject-linkage)
endif()
if(MAPNAV_WERROR)
  list(APPEND MAPNAV_WARNINGS -Werror)
endif()
if(MAPNAV_SANITIZERS)
  # No recovery: the first sanitizer report aborts the program, so a finding fails its test (UBSan
  # would otherwise print and carry on, and the test would pass).
  add_compile_options(-fsanitize=${MAPNAV_SANITIZERS} -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_link_options(-fsanitize=${MAPNAV_SANITIZERS})
  # The asan preset leaves out UBSan's alignment and null checks: they instrument every member access
  # and halve the compile speed of the CGAL and pixel files (clip.cpp 107 s -> 54 s), x86 loads
  # misaligned data correctly, and ASan reports a null dereference as a SEGV that fails the test too.
  if(MAPNAV_SANITIZERS_EXCLUDED)
    add_compile_options(-fno-sanitize=${MAPNAV_SANITIZERS_EXCLUDED})
  endif()
endif()

function(mapnav_module name)
  cmake_parse_arguments(M "INTERFACE" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  set(target mapnav_${name})
  if(M_INTERFACE)
    add_library(${target} INTERFACE)
    set(scope INTERFACE)
  else()
    add_library(${target} ${M_SOURCES})
    set(scope PUBLIC)
    target_compile_options(${target} PRIVATE ${MAPNAV_WARNINGS})
    target_link_libraries(${target} PRIVATE ${M_PRIVATE_DEPS})
    set_target_properties(${target} PROPERTIES OUTPUT_NAME mapnav_${name} VERSION ${PROJECT_VERSION}
      SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR})
  endif()
  add_library(mapnav::${name} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name})
  target_include_directories(${target} ${scope}
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_compile_features(${target} ${scope} cxx_std_20)
  target_link_libraries(${target} ${scope} ${M_PUBLIC_DEPS})
  install(TARGETS ${target} EXPORT mapnavTargets
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  if(EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/include)
    install(DIRECTORY include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  endif()
endfunction()
