# Installs the library with an exported CMake package, so a front end can
# find_package(sarmap) and link sarmap::sarmap.
get_property(SARMAP_MODULES GLOBAL PROPERTY SARMAP_MODULES)
install(TARGETS sarmap ${SARMAP_MODULES} sarmap_xsimd EXPORT sarmapTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(DIRECTORY engine kernels DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/sarmap
  FILES_MATCHING PATTERN "*.hpp")
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/generated/engine/core/version.hpp
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/sarmap/engine/core)
install(EXPORT sarmapTargets NAMESPACE sarmap::
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/sarmap)
configure_package_config_file(cmake/sarmapConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/sarmapConfig.cmake
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/sarmap)
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/sarmapConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/sarmapConfig.cmake
  ${CMAKE_CURRENT_BINARY_DIR}/sarmapConfigVersion.cmake
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/sarmap)
