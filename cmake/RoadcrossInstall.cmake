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

install(TARGETS roadcross RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT tools)
if(TARGET roadcross-build)
  install(TARGETS roadcross-build RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT tools)
endif()
if(TARGET roadcross-viz)  # beside roadcross, which runs it for render, export and view
  install(TARGETS roadcross-viz RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT tools)
endif()

# Debian packages: roadcross-runtime-dev (library, headers, CMake and pkg-config files),
# roadcross-tools (the executables) and python3-roadcross (the Python module, when
# built). `cpack -G DEB` in the build directory.
set(CPACK_PACKAGE_NAME roadcross)
set(CPACK_PACKAGE_VENDOR "roadcross")
set(CPACK_PACKAGE_CONTACT "roadcross maintainers <roadcross@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Where and how a pavement robot may cross a road")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL runtime tools)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_NAME roadcross-runtime-dev)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_DEPENDS "libsqlite3-dev, libgeographiclib-dev")
set(CPACK_DEBIAN_TOOLS_PACKAGE_NAME roadcross-tools)
set(CPACK_DEBIAN_TOOLS_PACKAGE_SHLIBDEPS ON)
# python3-roadcross: the Python module, for the interpreter it was built for.
if(TARGET roadcross_python)
  list(APPEND CPACK_COMPONENTS_ALL python)
  set(CPACK_DEBIAN_PYTHON_PACKAGE_NAME python3-roadcross)
  set(CPACK_DEBIAN_PYTHON_PACKAGE_SHLIBDEPS ON)
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
  set(CPACK_DEBIAN_ROS_PACKAGE_DEPENDS "python3-genpy, python3-std-msgs")
endif()
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_GENERATOR DEB)
include(CPack)
