# Installation of the runtime for robot controllers: the library, its public headers, a CMake
# package (find_package(roadcross) -> roadcross::runtime) and a pkg-config file
# (roadcross-runtime.pc). The runtime-only build installs exactly this, without GDAL, CGAL or
# libosmium. The tools (roadcross-build, roadcross) install into bin/.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(ROADCROSS_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/roadcross)

# The runtime is static: its two internal libraries ship with it.
set_target_properties(roadcross_runtime PROPERTIES EXPORT_NAME runtime)
set_target_properties(roadcross_geo PROPERTIES EXPORT_NAME geo)
set_target_properties(roadcross_schema PROPERTIES EXPORT_NAME schema)
install(TARGETS roadcross_runtime roadcross_geo roadcross_schema
        EXPORT roadcross-targets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT runtime
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/geo/include/roadcross ${PROJECT_SOURCE_DIR}/runtime/include/roadcross
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT runtime
        FILES_MATCHING PATTERN "*.hpp")
install(FILES ${PROJECT_BINARY_DIR}/generated/roadcross/version.hpp
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/roadcross COMPONENT runtime)
install(EXPORT roadcross-targets NAMESPACE roadcross:: DESTINATION ${ROADCROSS_INSTALL_CMAKEDIR}
        COMPONENT runtime)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/roadcrossConfig.cmake.in
  ${PROJECT_BINARY_DIR}/roadcrossConfig.cmake INSTALL_DESTINATION ${ROADCROSS_INSTALL_CMAKEDIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/roadcrossConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/roadcrossConfig.cmake ${PROJECT_BINARY_DIR}/roadcrossConfigVersion.cmake
        DESTINATION ${ROADCROSS_INSTALL_CMAKEDIR} COMPONENT runtime)

# pkg-config: paths are made relative to ${prefix} so the package is relocatable.
configure_file(${PROJECT_SOURCE_DIR}/cmake/roadcross-runtime.pc.in
               ${PROJECT_BINARY_DIR}/roadcross-runtime.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/roadcross-runtime.pc
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig COMPONENT runtime)

# roadcross, the query, verify and install commands: the robot's command line (component cli,
# package roadcross-cli), in the runtime-only build too. It links SQLite, GeographicLib and
# libcrypto only; render, export and view run roadcross-viz from the tools package.
install(TARGETS roadcross RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT cli)
if(TARGET roadcross-build)
  install(TARGETS roadcross-build RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT tools)
  # The GDAL module, opened by roadcross-build for elevation input (docs/architecture.md).
  install(TARGETS roadcross_gdal LIBRARY DESTINATION ${ROADCROSS_GDAL_MODULE_INSTALL_DIR}
          COMPONENT tools)
endif()
if(TARGET roadcross-viz)  # beside roadcross, which runs it for render, export and view
  install(TARGETS roadcross-viz RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT tools)
endif()

# Every package's /usr/share/doc/<package>/copyright (Debian's machine-readable format): the
# source is BSD-3-Clause (LICENSE); roadcross-tools says in addition that roadcross-build links
# CGAL's GPL-3 Triangulation_2 package, so that binary is GPL-3 as distributed.
file(READ ${PROJECT_SOURCE_DIR}/LICENSE roadcross_license)
string(STRIP "${roadcross_license}" roadcross_license)
string(REPLACE "\n\n" "\n.\n" roadcross_license "${roadcross_license}")
string(REPLACE "\n" "\n " ROADCROSS_BSD_TEXT " ${roadcross_license}")
function(roadcross_copyright component package template note)
  set(ROADCROSS_PACKAGE_NOTE "${note}")
  configure_file(${PROJECT_SOURCE_DIR}/cmake/copyright/${template}
                 ${PROJECT_BINARY_DIR}/copyright/${package}/copyright @ONLY)
  install(FILES ${PROJECT_BINARY_DIR}/copyright/${package}/copyright
          DESTINATION ${CMAKE_INSTALL_DATAROOTDIR}/doc/${package} COMPONENT ${component})
endfunction()
set(roadcross_permissive_note "links SQLite (public domain) and GeographicLib (MIT); no GPL code")
roadcross_copyright(runtime roadcross-runtime-dev permissive.copyright.in "${roadcross_permissive_note}")
roadcross_copyright(cli roadcross-cli permissive.copyright.in
  "${roadcross_permissive_note}; the command line also links OpenSSL's libcrypto (Apache-2.0)")

# Debian packages: roadcross-runtime-dev (library, headers, CMake and pkg-config files),
# roadcross-cli (the robot's command line: roadcross, without GDAL, Cairo, CGAL or libosmium),
# roadcross-tools (the workstation's map builder and drawing commands) and python3-roadcross
# (the Python module, when built). `cpack -G DEB` in the build directory.
set(CPACK_PACKAGE_NAME roadcross)
set(CPACK_PACKAGE_VENDOR "roadcross")
set(CPACK_PACKAGE_CONTACT "roadcross maintainers <roadcross@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Where and how a pavement robot may cross a road")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL runtime cli)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_NAME roadcross-runtime-dev)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_DEPENDS "libsqlite3-dev, libgeographiclib-dev")
set(CPACK_DEBIAN_CLI_PACKAGE_NAME roadcross-cli)
set(CPACK_DEBIAN_CLI_PACKAGE_SHLIBDEPS ON)
set(CPACK_COMPONENT_CLI_DESCRIPTION
    "roadcross command line for robots: query, verify and install maps (no GIS stack)")
# roadcross-tools: the workstation's roadcross-build and roadcross-viz (full build only).
if(TARGET roadcross-build)
  list(APPEND CPACK_COMPONENTS_ALL tools)
  set(CPACK_DEBIAN_TOOLS_PACKAGE_NAME roadcross-tools)
  set(CPACK_DEBIAN_TOOLS_PACKAGE_SHLIBDEPS ON)
  set(CPACK_DEBIAN_TOOLS_PACKAGE_DEPENDS "roadcross-cli (= ${PROJECT_VERSION})")
  set(CPACK_COMPONENT_TOOLS_DESCRIPTION
      "roadcross map builder and drawing commands for the workstation (roadcross-build is GPL-3 as distributed: it links CGAL)")
  roadcross_copyright(tools roadcross-tools tools.copyright.in "")
endif()
# python3-roadcross: the Python module, for the interpreter it was built for.
if(TARGET roadcross_python)
  list(APPEND CPACK_COMPONENTS_ALL python)
  set(CPACK_DEBIAN_PYTHON_PACKAGE_NAME python3-roadcross)
  set(CPACK_DEBIAN_PYTHON_PACKAGE_SHLIBDEPS ON)
  roadcross_copyright(python python3-roadcross permissive.copyright.in "${roadcross_permissive_note}")
  math(EXPR roadcross_python_next_minor "${Python_VERSION_MINOR} + 1")
  set(CPACK_DEBIAN_PYTHON_PACKAGE_DEPENDS
      "python3 (>= ${Python_VERSION_MAJOR}.${Python_VERSION_MINOR}), python3 (<< ${Python_VERSION_MAJOR}.${roadcross_python_next_minor})")
endif()
# roadcross-ros: the ROS1 node with its messages, services, launch and parameter files, in
# catkin's layout under the prefix (the node's libraries, roscpp among them, found by shlibdeps;
# the generated Python messages need rospy's message runtime).
if(TARGET roadcross_node)
  list(APPEND CPACK_COMPONENTS_ALL ros)
  set(CPACK_DEBIAN_ROS_PACKAGE_NAME roadcross-ros)
  set(CPACK_DEBIAN_ROS_PACKAGE_SHLIBDEPS ON)
  roadcross_copyright(ros roadcross-ros permissive.copyright.in
    "${roadcross_permissive_note}; the node also links roscpp (BSD-3-Clause)")
  set(CPACK_DEBIAN_ROS_PACKAGE_DEPENDS "python3-genpy, python3-std-msgs")
endif()
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_GENERATOR DEB)
include(CPack)
