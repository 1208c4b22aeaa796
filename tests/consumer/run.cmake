# ctest driver: install the build tree into a fresh prefix, build tests/consumer against it with
# find_package(mapnav), run it on the campus map and check what it prints.
# Inputs: -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... [-DSANITIZERS=address,undefined]
# Or, given PREFIX (an installed tree: tests/package/deb.cmake's unpacked .deb), only the consumer
# and plug-in builds against it, in WORK_DIR.
include(${CMAKE_CURRENT_LIST_DIR}/../support/run_steps.cmake)
if(NOT PREFIX)
  file(REMOVE_RECURSE "${WORK_DIR}")
  set(PREFIX "${WORK_DIR}/prefix")
  run(${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${PREFIX}")
endif()
# A sanitized mapnav needs a sanitized program: the sanitizer runtime must be loaded first.
set(flags "")
if(SANITIZERS)
  set(flags "-fsanitize=${SANITIZERS}")
endif()
run(${CMAKE_COMMAND} -S "${SOURCE_DIR}/tests/consumer" -B "${WORK_DIR}/build" -G Ninja
    "-DCMAKE_PREFIX_PATH=${PREFIX}" "-DCMAKE_CXX_FLAGS=${flags}")
run(${CMAKE_COMMAND} --build "${WORK_DIR}/build")
run("${WORK_DIR}/build/consumer" "${PREFIX}/share/mapnav/maps/cmu_campus.json")
if(NOT last_output MATCHES "^25 roads")
  message(FATAL_ERROR "unexpected consumer output: ${last_output}")
endif()
message(STATUS "consumer printed: ${last_output}")

# The example vision plug-in, built out of tree against the installed package, loads in mapnav.
run(${CMAKE_COMMAND} -S "${SOURCE_DIR}/examples/vision_plugin" -B "${WORK_DIR}/plugin" -G Ninja
    "-DCMAKE_PREFIX_PATH=${PREFIX}" "-DCMAKE_CXX_FLAGS=${flags}")
run(${CMAKE_COMMAND} --build "${WORK_DIR}/plugin")
run("${PREFIX}/bin/mapnav" pipelines --names --plugin "${WORK_DIR}/plugin/libmapnav_example_plugin.so")
if(NOT last_output MATCHES "example-lower-half")
  message(FATAL_ERROR "the out-of-tree plug-in was not listed: ${last_output}")
endif()
message(STATUS "pipelines with the plug-in: ${last_output}")
