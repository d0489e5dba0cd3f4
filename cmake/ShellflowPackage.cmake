# The installed CMake package: `cmake --install build --prefix P` writes
# P/lib/cmake/shellflow/{shellflowConfig,shellflowConfigVersion,shellflowTargets}.cmake
# and the out-of-tree shellflow_add_plugin() (cmake/package/ShellflowAddPlugin.cmake).
include(CMakePackageConfigHelpers)
set(SHELLFLOW_CMAKE_INSTALL_DIR lib/cmake/shellflow)
set(SHELLFLOW_INCLUDE_INSTALL_DIR include)
configure_package_config_file(
  ${PROJECT_SOURCE_DIR}/cmake/package/shellflowConfig.cmake.in
  ${PROJECT_BINARY_DIR}/cmake/shellflowConfig.cmake
  INSTALL_DESTINATION ${SHELLFLOW_CMAKE_INSTALL_DIR}
  PATH_VARS SHELLFLOW_INCLUDE_INSTALL_DIR SHELLFLOW_PLUGIN_INSTALL_DIR)
# 0.x: a minor version may break the SDK, so 0.1 accepts 0.1.z only.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/cmake/shellflowConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(EXPORT shellflowTargets NAMESPACE shellflow:: DESTINATION ${SHELLFLOW_CMAKE_INSTALL_DIR})
install(FILES
  ${PROJECT_BINARY_DIR}/cmake/shellflowConfig.cmake
  ${PROJECT_BINARY_DIR}/cmake/shellflowConfigVersion.cmake
  ${PROJECT_SOURCE_DIR}/cmake/package/ShellflowAddPlugin.cmake
  DESTINATION ${SHELLFLOW_CMAKE_INSTALL_DIR})
