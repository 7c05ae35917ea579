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
  mostar_target_settings(${name})
  if(NOT MOSTAR_SANITIZE STREQUAL "")
    # Sanitizer builds compile the test files themselves unoptimised (the code under test keeps
    # the build type's flags): test files are half of those builds and compile twice as fast.
    target_compile_options(${name} PRIVATE -O0)
  endif()
  if(MOSTAR_SANITIZE STREQUAL "thread")
    target_sources(${name} PRIVATE ${PROJECT_SOURCE_DIR}/cmake/tsan_opencv_serial.cc)
    target_link_libraries(${name} PRIVATE opencv_core)
  endif()
  # Tests find repository files (shipped configs, scenes) through MOSTAR_SOURCE_DIR (environment,
  # set by CTest) or the compile-time MOSTAR_TEST_SOURCE_DIR / MOSTAR_TEST_BINARY_DIR.
  target_compile_definitions(${name} PRIVATE MOSTAR_TEST_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    MOSTAR_TEST_BINARY_DIR="${PROJECT_BINARY_DIR}")
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
