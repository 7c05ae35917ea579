# cmake -DSOURCE_DIR=<repository root> -DBUILD_DIR=<build dir> -DCTEST=<ctest>
#       -P cmake/check_known_failures.cmake
# Fails (non-zero exit) when the tests registered with the label known_failure (which
# deploy/test.sh leaves out) are not exactly the tests docs/architecture.md names in its
# known_failure row: a label lost or added by an edit is caught either way. Registered as the
# CTest test known_failures_as_documented.
foreach(var SOURCE_DIR BUILD_DIR CTEST)
  if(NOT ${var})
    message(FATAL_ERROR "usage: cmake -DSOURCE_DIR=... -DBUILD_DIR=... -DCTEST=... "
                        "-P check_known_failures.cmake")
  endif()
endforeach()

# Documented: the backquoted test names of the table row that starts with | `known_failure` |.
file(STRINGS ${SOURCE_DIR}/docs/architecture.md rows REGEX "^\\| `known_failure` \\|")
list(LENGTH rows row_count)
if(NOT row_count EQUAL 1)
  message(FATAL_ERROR "docs/architecture.md: expected one known_failure row, found ${row_count}")
endif()
string(REGEX MATCHALL "`network_[a-z_]+`" documented "${rows}")
string(REPLACE "`" "" documented "${documented}")
list(REMOVE_DUPLICATES documented)
list(SORT documented)

# Registered: ctest -N -L known_failure lists "  Test #N: name".
execute_process(COMMAND ${CTEST} --test-dir ${BUILD_DIR} -N -L known_failure
  OUTPUT_VARIABLE listing RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "ctest -N -L known_failure failed (${status})")
endif()
string(REGEX MATCHALL "Test +#[0-9]+: [A-Za-z0-9_./-]+" entries "${listing}")
set(registered "")
foreach(entry IN LISTS entries)
  string(REGEX REPLACE "Test +#[0-9]+: " "" name "${entry}")
  list(APPEND registered ${name})
endforeach()
list(SORT registered)

if(NOT documented STREQUAL registered)
  message(FATAL_ERROR "known_failure tests differ from docs/architecture.md:\n"
                      "  registered: ${registered}\n  documented: ${documented}")
endif()
list(LENGTH registered count)
message(STATUS "known_failure: ${count} tests, as documented: ${registered}")
