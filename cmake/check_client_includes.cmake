# cmake -DSOURCE_DIR=<repository root> -P cmake/check_client_includes.cmake
# Fails (non-zero exit) when a file under operator_client/ includes a robot_server/ header
# (#include "robot_server/..." or <robot_server/...>) or a .proto there imports a robot_server/
# proto, naming each file and line. Registered as the CTest test client_includes_no_server_headers;
# the link side is checked at configure time (cmake/ClientBoundary.cmake).
if(NOT SOURCE_DIR)
  message(FATAL_ERROR "usage: cmake -DSOURCE_DIR=<repository root> -P check_client_includes.cmake")
endif()
file(GLOB_RECURSE files LIST_DIRECTORIES false
  ${SOURCE_DIR}/operator_client/*.h ${SOURCE_DIR}/operator_client/*.hh
  ${SOURCE_DIR}/operator_client/*.hpp ${SOURCE_DIR}/operator_client/*.c
  ${SOURCE_DIR}/operator_client/*.cc ${SOURCE_DIR}/operator_client/*.cpp
  ${SOURCE_DIR}/operator_client/*.inc ${SOURCE_DIR}/operator_client/*.proto)
list(LENGTH files file_count)
if(file_count EQUAL 0)
  message(FATAL_ERROR "no sources found under ${SOURCE_DIR}/operator_client")
endif()
set(violations "")
foreach(file IN LISTS files)
  file(STRINGS ${file} lines REGEX "robot_server/")
  foreach(line IN LISTS lines)
    if(line MATCHES "^[ \t]*#[ \t]*include[ \t]*[\"<]robot_server/"
       OR line MATCHES "^[ \t]*import[ \t]+(public[ \t]+|weak[ \t]+)?\"robot_server/")
      file(RELATIVE_PATH rel ${SOURCE_DIR} ${file})
      string(STRIP "${line}" line)
      string(APPEND violations "\n  ${rel}: ${line}")
    endif()
  endforeach()
endforeach()
if(violations)
  message(FATAL_ERROR "operator_client/ must not include robot_server/ headers:${violations}")
endif()
message(STATUS "checked ${file_count} files under operator_client/: no robot_server/ include")
