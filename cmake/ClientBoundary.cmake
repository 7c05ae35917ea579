# The operator client never depends on the server tree: no target defined in operator_client/
# (or below) may link, directly or through other project targets, a library defined in
# robot_server/ (or below). Checked once all targets exist, at configure time; a violation
# stops configuration with the client target, the server library and the link chain.
# The include side (no "robot_server/..." header in operator_client/ sources) is the CTest test
# client_includes_no_server_headers (cmake/check_client_includes.cmake).

# Sets <out> to every target defined in <dir> and its subdirectories.
function(_mostar_targets_below dir out)
  get_property(targets DIRECTORY ${dir} PROPERTY BUILDSYSTEM_TARGETS)
  get_property(subdirs DIRECTORY ${dir} PROPERTY SUBDIRECTORIES)
  foreach(subdir IN LISTS subdirs)
    _mostar_targets_below(${subdir} sub_targets)
    list(APPEND targets ${sub_targets})
  endforeach()
  set(${out} "${targets}" PARENT_SCOPE)
endfunction()

# Sets <out> to the targets <target> links directly (LINK_LIBRARIES and
# INTERFACE_LINK_LIBRARIES), aliases resolved. $<LINK_ONLY:x> (a static library's private
# dependency) counts as x; other generator expressions, the "::@" directory markers CMake
# inserts and plain library names or files are not targets and are skipped.
function(_mostar_linked_targets target out)
  set(linked "")
  foreach(property LINK_LIBRARIES INTERFACE_LINK_LIBRARIES)
    get_target_property(items ${target} ${property})
    if(NOT items)
      continue()
    endif()
    foreach(item IN LISTS items)
      string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" item "${item}")
      if(item MATCHES "^(\\$<|::@)" OR NOT TARGET "${item}")
        continue()
      endif()
      get_target_property(aliased "${item}" ALIASED_TARGET)
      if(aliased)
        set(item ${aliased})
      endif()
      list(APPEND linked "${item}")
    endforeach()
  endforeach()
  list(REMOVE_DUPLICATES linked)
  set(${out} "${linked}" PARENT_SCOPE)
endfunction()

# mostar_check_client_boundary(<client_dir> <server_dir>): FATAL_ERROR when a target defined
# under <client_dir> links a target defined under <server_dir>. Imported (external) targets
# are neither reported nor followed.
function(mostar_check_client_boundary client_dir server_dir)
  get_filename_component(server_dir "${server_dir}" ABSOLUTE)
  _mostar_targets_below(${client_dir} client_targets)
  foreach(client IN LISTS client_targets)
    set(queue ${client})
    set(seen ${client})
    set(chain_${client} ${client})
    while(queue)
      list(POP_FRONT queue current)
      _mostar_linked_targets(${current} linked)
      foreach(dep IN LISTS linked)
        if(dep IN_LIST seen)
          continue()
        endif()
        list(APPEND seen ${dep})
        get_target_property(imported ${dep} IMPORTED)
        if(imported)
          continue()
        endif()
        set(chain_${dep} "${chain_${current}} -> ${dep}")
        get_target_property(dep_dir ${dep} SOURCE_DIR)
        string(FIND "${dep_dir}/" "${server_dir}/" at)
        if(at EQUAL 0)
          file(RELATIVE_PATH where ${PROJECT_SOURCE_DIR} ${dep_dir})
          message(FATAL_ERROR "operator_client target '${client}' links robot_server library "
            "'${dep}' (defined in ${where}): ${chain_${dep}}. The client must not depend on "
            "the server tree; put code both need in common/, and tests that need the "
            "simulator in tests/.")
        endif()
        list(APPEND queue ${dep})
      endforeach()
    endwhile()
  endforeach()
endfunction()
