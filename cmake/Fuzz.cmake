# libFuzzer build: -DMAPNAV_FUZZ=ON, configured with CC=clang-14 CXX=clang++-14 in a build
# folder of its own (scripts/fuzz does this). Every library is compiled with coverage instrumentation
# for libFuzzer plus AddressSanitizer and UndefinedBehaviorSanitizer; the fuzz targets in tests/fuzz/
# are linked with -fsanitize=fuzzer. Undefined behaviour aborts (no recovery), so that libFuzzer
# reports it as a crash.
if(NOT MAPNAV_FUZZ)
  return()
endif()
if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  message(FATAL_ERROR "MAPNAV_FUZZ=ON needs clang with libFuzzer (Debian: clang-14 libclang-rt-14-dev); "
                      "configure a separate build folder with CC=clang-14 CXX=clang++-14 (see scripts/fuzz)")
endif()
if(MAPNAV_SANITIZERS)
  message(FATAL_ERROR "MAPNAV_FUZZ=ON already builds with address,undefined; leave MAPNAV_SANITIZERS empty")
endif()
set(MAPNAV_FUZZ_FLAGS -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
add_compile_options(-fsanitize=fuzzer-no-link ${MAPNAV_FUZZ_FLAGS})
add_link_options(${MAPNAV_FUZZ_FLAGS})
