# `cpack -G DEB` in the build folder: mapnav_<version>_amd64.deb with the libraries, headers and CMake
# package, the CLI, the Python module (in Debian's /usr/lib/python3/dist-packages), the maps and the
# docs, under /usr. Its dependencies: what dpkg-shlibdeps finds the binaries need (libc, libstdc++,
# OpenCV, libpng, ..., Torch for the learned pipeline when built), and Debian's python3 and numpy for
# the module; it recommends python3-distributed (mapnav.distributed, Dask).
# tests/package/deb.cmake builds it and installs it into a scratch root.
install(FILES README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR})
set(CPACK_PACKAGE_NAME mapnav)
set(CPACK_PACKAGE_VENDOR mapnav)
set(CPACK_PACKAGE_CONTACT "mapnav maintainers <mapnav@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "${PROJECT_DESCRIPTION}")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)   # the -g1 line tables stay in the build tree
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)   # mapnav_<version>_amd64.deb
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
if(MAPNAV_HAVE_PYTHON)   # the module is built for one Python minor version, as Debian's python3-* are
  math(EXPR next_minor "${Python3_VERSION_MINOR} + 1")
  set(CPACK_DEBIAN_PACKAGE_DEPENDS "python3 (>= ${Python3_VERSION_MAJOR}.${Python3_VERSION_MINOR}~), \
python3 (<< ${Python3_VERSION_MAJOR}.${next_minor}), python3-numpy")
  # mapnav.distributed needs Dask's scheduler; the core package does not pull it.
  set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "python3-distributed")
endif()
include(CPack)
