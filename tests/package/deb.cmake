# ctest driver: `cpack -G DEB` makes mapnav_<version>_amd64.deb with its dependencies declared;
# unpacked into a scratch root (dpkg -x, no installation), its CLI and Python module run from there,
# and tests/consumer and the example plug-in build against its CMake package (consumer/run.cmake).
# Inputs: -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... -DVERSION=... -DPYTHON=... -DCPACK=...
file(REMOVE_RECURSE "${WORK_DIR}")
include(${CMAKE_CURRENT_LIST_DIR}/../support/run_steps.cmake)

run("${CPACK}" -G DEB --config "${BUILD_DIR}/CPackConfig.cmake" -B "${WORK_DIR}")
set(deb "${WORK_DIR}/mapnav_${VERSION}_amd64.deb")
if(NOT EXISTS "${deb}")
  file(GLOB made "${WORK_DIR}/*.deb")
  message(FATAL_ERROR "no ${deb}; cpack made: ${made}")
endif()
run(dpkg-deb --field "${deb}" Depends)
expect("python3-numpy.*libc6 \\(>= [0-9.]+\\).*libopencv-core" "Depends")
run(dpkg-deb --field "${deb}" Recommends)   # Dask for mapnav.distributed, not a dependency of the core
expect("^python3-distributed\n$" "Recommends")

set(root "${WORK_DIR}/root")
run(dpkg -x "${deb}" "${root}")
run("${root}/usr/bin/mapnav" --version)
expect("${VERSION}" "mapnav --version")
run(${CMAKE_COMMAND} -E env "PYTHONPATH=${root}/usr/lib/python3/dist-packages" "${PYTHON}" -c
    "import mapnav\nprint(mapnav.__version__, mapnav.__file__, len(mapnav.Map.load('${root}/usr/share/mapnav/maps/cmu_campus.json').road_ids))")
expect("^${VERSION} ${root}/usr/lib/python3/dist-packages/mapnav/__init__.py 25\n$" "import mapnav")
# mapnav.distributed is in the package and finds the shipped camera beside it, not in the source tree.
run(${CMAKE_COMMAND} -E env "PYTHONPATH=${root}/usr/lib/python3/dist-packages" "${PYTHON}" -c
    "from mapnav import distributed\nprint(distributed._data_file('maps/cameras/terregator_pinhole.json'))")
expect("^${root}/usr/share/mapnav/maps/cameras/terregator_pinhole.json\n$" "mapnav.distributed's data")

set(PREFIX "${root}/usr")
set(WORK_DIR "${WORK_DIR}/consumer")
include("${SOURCE_DIR}/tests/consumer/run.cmake")
