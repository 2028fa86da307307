# cmake --install: the programs, every scene, the loopback DDS config, the systemd unit (with the
# real prefix) and the client SDK (headers, static libraries, rigidConfig.cmake with rigid::client,
# rigid.pc). Included from the top-level CMakeLists.txt after every target exists. The Python
# package installs itself (clients/python/CMakeLists.txt, RIGID_PYTHON_INSTALL_DIR).
include(CMakePackageConfigHelpers)

install(TARGETS rigidd rigid-sim rigidctl rigid-record rigid-attitude rigid-view
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# rigid-view's page (and the three.js it serves), as the build copies it next to the executable;
# an installed rigid-view finds it at ../share/rigid/web from its own directory.
install(DIRECTORY ${PROJECT_BINARY_DIR}/clients/view/web/
        DESTINATION ${CMAKE_INSTALL_DATADIR}/rigid/web)
install(PROGRAMS ${PROJECT_SOURCE_DIR}/scripts/rigid-keys DESTINATION ${CMAKE_INSTALL_BINDIR})

file(GLOB _rigid_scenes CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/config/scenes/*.pbtxt)
install(FILES ${_rigid_scenes} DESTINATION ${CMAKE_INSTALL_DATADIR}/rigid/scenes)
install(FILES ${PROJECT_SOURCE_DIR}/config/cyclonedds.xml ${PROJECT_SOURCE_DIR}/config/cyclonedds-ros.xml
        DESTINATION ${CMAKE_INSTALL_DATADIR}/rigid)

# The unit names the installed rigidd, scene and DDS config: configured when installing, so that
# the prefix is the one installed to (cmake --install --prefix P as well as CMAKE_INSTALL_PREFIX).
install(CODE "
  set(RIGID_BINDIR \"\${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_BINDIR}\")
  set(RIGID_DATADIR \"\${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_DATADIR}/rigid\")
  set(_unit \"\$ENV{DESTDIR}\${CMAKE_INSTALL_PREFIX}/lib/systemd/system/rigidd.service\")
  message(STATUS \"Installing: \${_unit}\")
  configure_file(\"${PROJECT_SOURCE_DIR}/config/rigidd.service.in\" \"\${_unit}\" @ONLY)
  list(APPEND CMAKE_INSTALL_MANIFEST_FILES \"\${_unit}\")
")

# The SDK. rigid_client is static; what it links privately (the transports, the generated DDS
# types, liblcm, libddsc, libcrypto, threads) is installed or named in the exported targets, so a
# consumer links with rigid::client alone.
install(TARGETS rigid_client rigid_messages rigid_transport rigid_transport_dds
                rigid_transport_lcm rigid_dds_msgs rigid_lcm_msgs
        EXPORT rigidTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/msgs/include/rigid
                  ${PROJECT_SOURCE_DIR}/clients/client/include/rigid
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} FILES_MATCHING PATTERN "*.hpp")
set(RIGID_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/rigid)
install(EXPORT rigidTargets NAMESPACE rigid:: DESTINATION ${RIGID_CMAKE_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/rigidConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/rigidConfig.cmake
                              INSTALL_DESTINATION ${RIGID_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/rigidConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/rigidConfig.cmake ${PROJECT_BINARY_DIR}/rigidConfigVersion.cmake
        DESTINATION ${RIGID_CMAKE_DIR})
# pkg-config: prefix relative to the .pc file's place (pcfiledir), so any install prefix works.
file(RELATIVE_PATH RIGID_PC_TO_PREFIX
     ${CMAKE_INSTALL_FULL_LIBDIR}/pkgconfig ${CMAKE_INSTALL_PREFIX})
string(REGEX REPLACE "/$" "" RIGID_PC_TO_PREFIX "${RIGID_PC_TO_PREFIX}")
configure_file(${PROJECT_SOURCE_DIR}/cmake/rigid.pc.in ${PROJECT_BINARY_DIR}/rigid.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/rigid.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
