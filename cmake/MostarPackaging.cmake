# Install rules and Debian packages (deploy/package.sh builds them; docs/packages.md).
#
#   mostar-common    the example configurations, scenes, calibration and DDS profiles
#                    (/usr/share/mostar), the PKI and overlay scripts (mostar-make-pki,
#                    mostar-revoke, mostar-make-overlay, mostar-hub-endpoints), the
#                    WireGuard-over-TCP tunnel (mostar_wg_tcp and its client unit), the
#                    mostar user and group (sysusers.d) and folders (tmpfiles.d), the
#                    documentation
#   mostar-robot     robot_server, its unit and udev rules, /etc/mostar/server.pbtxt (conffile)
#   mostar-operator  operator_client and mostar_web
#   mostar-hub       mostar_relay and the hub's units (relay, TCP fallback server, the
#                    timer saving its peers' endpoints)
#
# The paths follow GNUInstallDirs; with CMAKE_INSTALL_PREFIX=/usr (the packages) the
# configuration goes to /etc, units and udev rules to /lib as on Debian 12.
include_guard(GLOBAL)

set(MOSTAR_PACKAGE_MAINTAINER "mostar maintainers <mostar-maintainers@example.org>"
  CACHE STRING "Maintainer field of the Debian packages")
set(MOSTAR_SHARE_DIR ${CMAKE_INSTALL_DATADIR}/mostar)
set(MOSTAR_ETC_DIR ${CMAKE_INSTALL_FULL_SYSCONFDIR}/mostar)
if(CMAKE_INSTALL_PREFIX STREQUAL "/usr")
  set(MOSTAR_UNIT_DIR /lib/systemd/system)
  set(MOSTAR_UDEV_DIR /lib/udev/rules.d)
else()
  set(MOSTAR_UNIT_DIR ${CMAKE_INSTALL_LIBDIR}/systemd/system)
  set(MOSTAR_UDEV_DIR ${CMAKE_INSTALL_LIBDIR}/udev/rules.d)
endif()

# --- mostar-common
file(MAKE_DIRECTORY ${PROJECT_BINARY_DIR}/packaging)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/deploy/config ${PROJECT_SOURCE_DIR}/deploy/scenes
                  ${PROJECT_SOURCE_DIR}/deploy/calibration ${PROJECT_SOURCE_DIR}/deploy/dds
  DESTINATION ${MOSTAR_SHARE_DIR} COMPONENT common)
install(PROGRAMS ${PROJECT_SOURCE_DIR}/deploy/security/make_pki.sh
                 ${PROJECT_SOURCE_DIR}/deploy/security/revoke.sh
  DESTINATION ${MOSTAR_SHARE_DIR}/security COMPONENT common)
install(PROGRAMS ${PROJECT_SOURCE_DIR}/deploy/wan/make_overlay.sh
                 ${PROJECT_SOURCE_DIR}/deploy/wan/hub_endpoints.sh
  DESTINATION ${MOSTAR_SHARE_DIR}/wan COMPONENT common)
# The scripts find their templates beside them (../dds) through the links.
foreach(link mostar-make-pki:security/make_pki.sh mostar-revoke:security/revoke.sh
             mostar-make-overlay:wan/make_overlay.sh mostar-hub-endpoints:wan/hub_endpoints.sh)
  string(REPLACE ":" ";" link "${link}")
  list(GET link 0 name)
  list(GET link 1 target)
  file(RELATIVE_PATH rel ${CMAKE_INSTALL_FULL_BINDIR} ${CMAKE_INSTALL_FULL_DATADIR}/mostar/${target})
  file(CREATE_LINK ${rel} ${PROJECT_BINARY_DIR}/packaging/${name} SYMBOLIC)
  install(FILES ${PROJECT_BINARY_DIR}/packaging/${name} DESTINATION ${CMAKE_INSTALL_BINDIR}
    COMPONENT common)
endforeach()
install(TARGETS mostar_wg_tcp RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT common)
install(FILES ${PROJECT_SOURCE_DIR}/deploy/systemd/mostar-wg-tcp.service
  DESTINATION ${MOSTAR_UNIT_DIR} COMPONENT common)
install(FILES ${PROJECT_SOURCE_DIR}/deploy/packaging/mostar.sysusers
  DESTINATION lib/sysusers.d RENAME mostar.conf COMPONENT common)
install(FILES ${PROJECT_SOURCE_DIR}/deploy/packaging/mostar.tmpfiles
  DESTINATION lib/tmpfiles.d RENAME mostar.conf COMPONENT common)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR}
  COMPONENT common)

# --- mostar-robot
install(TARGETS robot_server RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT robot)
install(FILES ${PROJECT_SOURCE_DIR}/deploy/systemd/mostar-robot-server.service
  DESTINATION ${MOSTAR_UNIT_DIR} COMPONENT robot)
file(GLOB _mostar_udev_rules ${PROJECT_SOURCE_DIR}/deploy/udev/*.rules)
install(FILES ${_mostar_udev_rules} DESTINATION ${MOSTAR_UDEV_DIR} COMPONENT robot)
install(FILES ${PROJECT_SOURCE_DIR}/deploy/config/server_morduc.pbtxt
  DESTINATION ${MOSTAR_ETC_DIR} RENAME server.pbtxt COMPONENT robot)

# --- mostar-operator
if(MOSTAR_BUILD_CLIENT)
  install(TARGETS operator_client mostar_web RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
    COMPONENT operator)

  # --- mostar-hub
  install(TARGETS mostar_relay RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT hub)
  install(FILES ${PROJECT_SOURCE_DIR}/deploy/systemd/mostar-relay.service
                ${PROJECT_SOURCE_DIR}/deploy/systemd/mostar-wg-tcp-hub.service
                ${PROJECT_SOURCE_DIR}/deploy/systemd/mostar-hub-endpoints.service
                ${PROJECT_SOURCE_DIR}/deploy/systemd/mostar-hub-endpoints.timer
    DESTINATION ${MOSTAR_UNIT_DIR} COMPONENT hub)
endif()

# --- manual pages: help2man from each program's --help (section 1, gzipped as Debian policy
# 12.1 asks), built with `all` and by the target `man_pages`. Without help2man (a developer's
# computer) there are none; deploy/install-deps.sh installs it.
find_program(MOSTAR_HELP2MAN help2man)
if(MOSTAR_HELP2MAN)
  set(_mostar_man_dir ${PROJECT_BINARY_DIR}/man)
  file(MAKE_DIRECTORY ${_mostar_man_dir})
  set(_mostar_man_pages)
  # A page for the command NAME run as EXECUTABLE_NAME from DIRECTORY (so that its usage line
  # says the bare name, not a build path), installed with COMPONENT.
  function(mostar_man_page name directory executable_name component summary depends)
    set(page ${_mostar_man_dir}/${name}.1)
    add_custom_command(OUTPUT ${page}.gz
      COMMAND ${CMAKE_COMMAND} -E env "PATH=${directory}:/usr/bin:/bin" ${MOSTAR_HELP2MAN}
              --no-info --no-discard-stderr --section=1 --name=${summary}
              "--version-string=${name} ${PROJECT_VERSION}" --output=${page} ${executable_name}
      COMMAND gzip -9nf ${page}
      DEPENDS ${depends}
      COMMENT "Manual page ${name}(1)" VERBATIM)
    set(_mostar_man_pages ${_mostar_man_pages} ${page}.gz PARENT_SCOPE)
    install(FILES ${page}.gz DESTINATION ${CMAKE_INSTALL_MANDIR}/man1 COMPONENT ${component})
  endfunction()
  set(_mostar_programs "robot_server|robot|the mostar robot daemon: sensors, video and driving over DDS"
    "mostar_wg_tcp|common|the WireGuard overlay's datagrams over TCP where UDP is blocked")
  if(MOSTAR_BUILD_CLIENT)
    list(APPEND _mostar_programs
      "operator_client|operator|the mostar operator console: stereoscopic AR view and driving"
      "mostar_web|operator|the robot's AR view in any browser, read-only"
      "mostar_relay|hub|forwards the robot's streams to many observers and their e-stops to the robot")
  endif()
  foreach(entry IN LISTS _mostar_programs)
    string(REPLACE "|" ";" entry "${entry}")
    list(GET entry 0 target)
    list(GET entry 1 component)
    list(GET entry 2 summary)
    mostar_man_page(${target} $<TARGET_FILE_DIR:${target}> $<TARGET_FILE_NAME:${target}>
                    ${component} ${summary} ${target})
  endforeach()
  foreach(entry "mostar-make-pki|security/make_pki.sh|make the DDS Security PKI: CAs, certificates, permissions, host bundles"
                "mostar-revoke|security/revoke.sh|revoke a participant's certificate and issue a new CRL"
                "mostar-make-overlay|wan/make_overlay.sh|make the WireGuard overlay: the hub's and every peer's configuration"
                "mostar-hub-endpoints|wan/hub_endpoints.sh|keep the overlay hub's peer endpoints across a restart")
    string(REPLACE "|" ";" entry "${entry}")
    list(GET entry 0 name)
    list(GET entry 1 script)
    list(GET entry 2 summary)
    get_filename_component(script_dir ${PROJECT_SOURCE_DIR}/deploy/${script} DIRECTORY)
    get_filename_component(script_name ${script} NAME)
    mostar_man_page(${name} ${script_dir} ${script_name} common ${summary}
                    ${PROJECT_SOURCE_DIR}/deploy/${script})
  endforeach()
  add_custom_target(man_pages ALL DEPENDS ${_mostar_man_pages})
else()
  message(STATUS "help2man not found: no manual pages (deploy/install-deps.sh installs it)")
endif()

# Each package's /usr/share/doc/PACKAGE: copyright and changelog.Debian.gz (Debian policy 12.5, 12.7).
string(TIMESTAMP _mostar_changelog_date "%a, %d %b %Y %H:%M:%S +0000" UTC)
file(WRITE ${PROJECT_BINARY_DIR}/packaging/changelog.Debian
  "mostar (${PROJECT_VERSION}-1) unstable; urgency=medium\n\n"
  "  * Built from the mostar source tree (git log for the changes).\n\n"
  " -- ${MOSTAR_PACKAGE_MAINTAINER}  ${_mostar_changelog_date}\n")
execute_process(COMMAND gzip -9nf ${PROJECT_BINARY_DIR}/packaging/changelog.Debian
  COMMAND_ERROR_IS_FATAL ANY)
foreach(component common robot operator hub)
  install(FILES ${PROJECT_SOURCE_DIR}/deploy/packaging/copyright
                ${PROJECT_BINARY_DIR}/packaging/changelog.Debian.gz
    DESTINATION ${CMAKE_INSTALL_DATAROOTDIR}/doc/mostar-${component} COMPONENT ${component})
endforeach()

# --- Debian packages (cpack -G DEB)
set(CPACK_PACKAGE_NAME mostar)
set(CPACK_PACKAGE_VENDOR "mostar")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
# No CPACK_PACKAGE_DESCRIPTION_SUMMARY: each package's first description line is its synopsis.
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${MOSTAR_PACKAGE_MAINTAINER}")
set(CPACK_GENERATOR DEB)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_DEBIAN_ENABLE_COMPONENT_DEPENDS ON)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)  # Depends computed from the binaries (dpkg-shlibdeps)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION misc)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_RELEASE 1)
set(CPACK_PACKAGING_INSTALL_PREFIX ${CMAKE_INSTALL_PREFIX})
set(CPACK_STRIP_FILES ON)
set(CPACK_OUTPUT_FILE_PREFIX ${PROJECT_BINARY_DIR}/packages)
set(CPACK_COMPONENTS_ALL common robot)
if(MOSTAR_BUILD_CLIENT)
  list(APPEND CPACK_COMPONENTS_ALL operator hub)
endif()

# Per package: name, description, extra Depends, maintainer scripts and conffiles.
set(_pkg ${PROJECT_BINARY_DIR}/packaging)
function(mostar_deb_control component)
  cmake_parse_arguments(ARG "" "POSTINST;CONFFILES" "" ${ARGN})
  string(TOUPPER ${component} C)
  set(files "")
  if(ARG_POSTINST)
    set(PACKAGE mostar-${component})
    configure_file(${PROJECT_SOURCE_DIR}/deploy/packaging/${ARG_POSTINST}
      ${_pkg}/${component}/postinst @ONLY
      FILE_PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE
                       WORLD_READ WORLD_EXECUTE)
    list(APPEND files ${_pkg}/${component}/postinst)
  endif()
  if(ARG_CONFFILES)
    file(WRITE ${_pkg}/${component}/conffiles "${ARG_CONFFILES}\n")
    list(APPEND files ${_pkg}/${component}/conffiles)
  endif()
  set(CPACK_DEBIAN_${C}_PACKAGE_CONTROL_EXTRA "${files}" PARENT_SCOPE)
  set(CPACK_DEBIAN_${C}_PACKAGE_CONTROL_STRICT_PERMISSION TRUE PARENT_SCOPE)
endfunction()

set(CPACK_DEBIAN_COMMON_PACKAGE_NAME mostar-common)
set(CPACK_DEBIAN_COMMON_DESCRIPTION
    "mostar teleoperation: examples, DDS profiles, PKI and overlay tools, TCP tunnel\n\
Example configurations of the robot server and the operator console,\n\
simulator scenes, DDS profiles for loopback, LAN and the WireGuard overlay,\n\
the scripts that make the DDS Security PKI and the overlay, the WireGuard-\n\
over-TCP tunnel for networks that block UDP, and the mostar system user\n\
shared by the services.")
set(CPACK_DEBIAN_COMMON_PACKAGE_DEPENDS "openssl, passwd")
set(CPACK_DEBIAN_COMMON_PACKAGE_RECOMMENDS "wireguard-tools")
mostar_deb_control(common POSTINST postinst-common.in)

set(CPACK_DEBIAN_ROBOT_PACKAGE_NAME mostar-robot)
set(CPACK_DEBIAN_ROBOT_DESCRIPTION
    "mostar teleoperation: the robot server\n\
robot_server reads the SICK LMS200, the stereo cameras, the sonars and\n\
bumpers, drives the differential base under its safety rules, and publishes\n\
everything over DDS; a systemd unit with a watchdog, udev rules for the\n\
laser, the motor board and the cameras.")
set(CPACK_COMPONENT_ROBOT_DEPENDS common)
mostar_deb_control(robot POSTINST postinst-units.in CONFFILES "${MOSTAR_ETC_DIR}/server.pbtxt")

set(CPACK_DEBIAN_OPERATOR_PACKAGE_NAME mostar-operator)
set(CPACK_DEBIAN_OPERATOR_DESCRIPTION
    "mostar teleoperation: the operator console and the web observer\n\
operator_client shows the robot's stereo video with the laser fused in as\n\
augmented reality (OpenGL) and drives it from the keyboard or a gamepad;\n\
mostar_web lets observers watch from a web browser.")
set(CPACK_COMPONENT_OPERATOR_DEPENDS common)

set(CPACK_DEBIAN_HUB_PACKAGE_NAME mostar-hub)
set(CPACK_DEBIAN_HUB_DESCRIPTION
    "mostar teleoperation: the overlay hub's relay\n\
mostar_relay takes the robot's streams once and passes them to any number of\n\
observers and the pilot; units for the relay and for the hub's end of the\n\
TCP fallback.")
set(CPACK_COMPONENT_HUB_DEPENDS common)
set(CPACK_DEBIAN_HUB_PACKAGE_DEPENDS "wireguard-tools, nftables")
set(CPACK_DEBIAN_HUB_PACKAGE_SUGGESTS "wireguard-go")
mostar_deb_control(hub POSTINST postinst-units.in)

include(CPack)
