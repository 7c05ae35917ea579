# Shared compile settings, applied per target (no global flags or include directories).

set(MOSTAR_WARNINGS -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wold-style-cast
    -Wcast-align -Woverloaded-virtual -Wnull-dereference -Wimplicit-fallthrough)
if(MOSTAR_WERROR)
  list(APPEND MOSTAR_WARNINGS -Werror)
endif()

set(MOSTAR_SANITIZER_FLAGS "")
if(MOSTAR_SANITIZE STREQUAL "address")
  set(MOSTAR_SANITIZER_FLAGS -fsanitize=address,undefined -fno-omit-frame-pointer
      -fno-sanitize-recover=undefined)
elseif(MOSTAR_SANITIZE STREQUAL "thread")
  set(MOSTAR_SANITIZER_FLAGS -fsanitize=thread -fno-omit-frame-pointer)
elseif(NOT MOSTAR_SANITIZE STREQUAL "")
  message(FATAL_ERROR "MOSTAR_SANITIZE must be '', 'address' or 'thread'")
endif()

# mostar_target_settings(<target>): warnings and sanitizers for the project's own code.
function(mostar_target_settings target)
  target_compile_options(${target} PRIVATE ${MOSTAR_WARNINGS} ${MOSTAR_SANITIZER_FLAGS})
  target_link_options(${target} PRIVATE ${MOSTAR_SANITIZER_FLAGS})
endfunction()

# mostar_library(<name> SOURCES ... DEPS ...): one static library per concern folder.
# Headers are included as "folder/file.h" from the repository root.
function(mostar_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_library(${name} STATIC ${ARG_SOURCES})
  target_include_directories(${name} PUBLIC ${PROJECT_SOURCE_DIR})
  target_link_libraries(${name} PUBLIC ${ARG_DEPS})
  mostar_target_settings(${name})
endfunction()

# Test files spend most of their compile time parsing the same headers (GoogleTest, Eigen,
# OpenCV, the standard library). mostar_test_pch precompiles them once per build directory with
# exactly a test file's flags, and every mostar_test reuses it. MOSTAR_TEST_PCH=OFF compiles
# every test file from its own includes (each file still includes what it uses).
option(MOSTAR_TEST_PCH "Precompile the headers that test files share" ON)

# mostar_test_compile_settings(<target>): the flags of a test file (also those of the test PCH,
# which must be identical for the compiler to accept it).
function(mostar_test_compile_settings target)
  mostar_target_settings(${target})
  # Test files themselves are compiled with little optimisation (the code under test keeps the
  # build type's flags; benchmarks are not tests): they are half of every build. Sanitizer builds
  # compile them unoptimised, others at -O1, which keeps the warnings that need data-flow
  # analysis (-Wmaybe-uninitialized, -Wnull-dereference).
  if(NOT MOSTAR_SANITIZE STREQUAL "")
    target_compile_options(${target} PRIVATE -O0)
  elseif(NOT CMAKE_BUILD_TYPE STREQUAL "Debug")
    target_compile_options(${target} PRIVATE -O1)
  endif()
  # Tests find repository files (shipped configs, scenes) through MOSTAR_SOURCE_DIR (environment,
  # set by CTest) or the compile-time MOSTAR_TEST_SOURCE_DIR / MOSTAR_TEST_BINARY_DIR.
  target_compile_definitions(${target} PRIVATE MOSTAR_TEST_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    MOSTAR_TEST_BINARY_DIR="${PROJECT_BINARY_DIR}")
endfunction()

# mostar_add_test_pch(): call once, after GTest, Eigen and OpenCV were found and before any
# mostar_test.
function(mostar_add_test_pch)
  if(NOT MOSTAR_TEST_PCH)
    return()
  endif()
  add_library(mostar_test_pch STATIC ${PROJECT_SOURCE_DIR}/cmake/test_pch.cc)
  target_link_libraries(mostar_test_pch PRIVATE GTest::gtest GTest::gmock Eigen3::Eigen
    opencv_core opencv_imgproc)
  mostar_test_compile_settings(mostar_test_pch)
  target_precompile_headers(mostar_test_pch PRIVATE
    <algorithm> <atomic> <chrono> <cmath> <cstdint> <cstdio> <cstring> <functional> <map>
    <memory> <mutex> <optional> <sstream> <string> <thread> <utility> <vector>
    <gtest/gtest.h> <gmock/gmock.h> <Eigen/Core> <Eigen/Geometry> <opencv2/core.hpp>
    <opencv2/imgproc.hpp>)
endfunction()

# mostar_test(<name> SOURCES ... DEPS ... [LABELS ...]): a GoogleTest executable registered
# with CTest. Each test process gets its own DDS domain id (see common/dds/domain.h).
# Labels:
#   e2e, timing  real programs in other processes, with timing expectations: RUN_SERIAL, so that
#                they never share the cores with another test (the 60 s fuzzer included)
#   gl           needs an X display (Xvfb)
#   concurrency  threads meeting (camera pipeline, edge worker, DDS callbacks, outbox): the
#                thread-sanitizer build runs these (target concurrency_tests, ctest -L concurrency)
# Every other test is labelled "unit": in-process, no display; the address-sanitizer build runs
# them (target unit_tests, ctest -L unit).
function(mostar_test name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS;LABELS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} GTest::gtest GTest::gmock GTest::gtest_main)
  mostar_test_compile_settings(${name})
  if(MOSTAR_TEST_PCH)
    # -Winvalid-pch (an error with MOSTAR_WERROR): a test whose flags differ from the PCH's fails
    # to build instead of silently parsing every header again.
    target_precompile_headers(${name} REUSE_FROM mostar_test_pch)
    target_compile_options(${name} PRIVATE -Winvalid-pch)
  endif()
  if(MOSTAR_SANITIZE STREQUAL "thread")
    target_sources(${name} PRIVATE ${PROJECT_SOURCE_DIR}/cmake/tsan_opencv_serial.cc)
    target_link_libraries(${name} PRIVATE opencv_core)
  endif()
  set(properties TIMEOUT 300 ENVIRONMENT "MOSTAR_SOURCE_DIR=${PROJECT_SOURCE_DIR}")
  set(labels ${ARG_LABELS})
  if(NOT "e2e" IN_LIST labels AND NOT "timing" IN_LIST labels AND NOT "gl" IN_LIST labels)
    list(APPEND labels unit)
    set_property(GLOBAL APPEND PROPERTY MOSTAR_UNIT_TEST_TARGETS ${name})
  endif()
  if("concurrency" IN_LIST labels)
    set_property(GLOBAL APPEND PROPERTY MOSTAR_CONCURRENCY_TEST_TARGETS ${name})
  endif()
  if("e2e" IN_LIST labels OR "timing" IN_LIST labels)
    list(APPEND properties RUN_SERIAL TRUE)
  endif()
  list(APPEND properties LABELS "${labels}")
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60 PROPERTIES ${properties})
endfunction()

# Targets that build the tests of one kind (for the sanitizer builds): unit_tests and
# concurrency_tests. Call once, after every folder was added.
function(mostar_test_groups)
  get_property(unit GLOBAL PROPERTY MOSTAR_UNIT_TEST_TARGETS)
  get_property(concurrency GLOBAL PROPERTY MOSTAR_CONCURRENCY_TEST_TARGETS)
  add_custom_target(unit_tests)
  add_dependencies(unit_tests ${unit})
  add_custom_target(concurrency_tests)
  add_dependencies(concurrency_tests ${concurrency})
endfunction()

# mostar_benchmark(<name> SOURCES ... DEPS ...): a Google Benchmark executable (not a test).
function(mostar_benchmark name)
  if(NOT MOSTAR_BUILD_BENCHMARKS)
    return()
  endif()
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} benchmark::benchmark benchmark::benchmark_main)
  mostar_target_settings(${name})
endfunction()

# mostar_proto_library(<name> PROTOS a.proto ... [DEPS ...]): a library of generated protobuf
# code. Protos import each other by repository path ("common/config/options.proto"), and
# consumers include "<folder>/<file>.pb.h".
function(mostar_proto_library name)
  cmake_parse_arguments(ARG "" "" "PROTOS;DEPS" ${ARGN})
  set(out ${PROJECT_BINARY_DIR}/gen/proto)
  set(sources "")
  foreach(proto ${ARG_PROTOS})
    get_filename_component(abs ${proto} ABSOLUTE)
    file(RELATIVE_PATH rel ${PROJECT_SOURCE_DIR} ${abs})
    string(REGEX REPLACE "\\.proto$" "" stem ${rel})
    add_custom_command(
      OUTPUT ${out}/${stem}.pb.cc ${out}/${stem}.pb.h
      COMMAND ${CMAKE_COMMAND} -E make_directory ${out}
      COMMAND protobuf::protoc --cpp_out=${out} -I ${PROJECT_SOURCE_DIR} ${abs}
      DEPENDS ${abs} protobuf::protoc
      COMMENT "protoc ${rel}"
      VERBATIM)
    list(APPEND sources ${out}/${stem}.pb.cc)
  endforeach()
  add_library(${name} STATIC ${sources})
  target_include_directories(${name} SYSTEM PUBLIC ${out})
  target_link_libraries(${name} PUBLIC protobuf::libprotobuf ${ARG_DEPS})
  target_compile_options(${name} PRIVATE -w)
endfunction()
