# Install-time part of packaging/CMakeLists.txt: the files whose contents or place depend on
# the prefix of this install, which `cmake --install --prefix` and CPack decide only now.

# GNUInstallDirs' rule for the prefix /usr (the package): the config lives in /etc.
if(IS_ABSOLUTE "${UNIMA_SYSCONFDIR}")
  set(sysconfdir "${UNIMA_SYSCONFDIR}")
elseif(CMAKE_INSTALL_PREFIX STREQUAL "/usr")
  set(sysconfdir "/${UNIMA_SYSCONFDIR}")
else()
  set(sysconfdir "${CMAKE_INSTALL_PREFIX}/${UNIMA_SYSCONFDIR}")
endif()
set(config_file "${sysconfdir}/unima-bridge/bridge.yaml")
set(daemon_file "${CMAKE_INSTALL_PREFIX}/${UNIMA_SBINDIR}/unima-bridged")

# The default config, never over an operator's edited one (the package's conffile handling
# does that job for the .deb).
if(EXISTS "$ENV{DESTDIR}${config_file}")
  message(STATUS "Keeping: $ENV{DESTDIR}${config_file} (the default is in the docs' examples/bridge.yaml)")
else()
  file(INSTALL DESTINATION "${sysconfdir}/unima-bridge" TYPE FILE FILES "${UNIMA_SOURCE_DIR}/packaging/bridge.yaml")
endif()

# The unit as written names the package's paths; another prefix gets its own.
set(unit_file "$ENV{DESTDIR}${CMAKE_INSTALL_PREFIX}/${UNIMA_SYSTEMD_UNIT_DIR}/unima-bridge.service")
file(READ "${unit_file}" unit)
string(REPLACE "/usr/sbin/unima-bridged" "${daemon_file}" unit "${unit}")
string(REPLACE "/etc/unima-bridge/bridge.yaml" "${config_file}" unit "${unit}")
file(WRITE "${unit_file}" "${unit}")
