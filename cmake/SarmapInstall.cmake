# Installs the library with an exported CMake package, so a front end can
# find_package(sarmap) and link sarmap::sarmap, and the data the sarmap binary
# uses by default into share/sarmap/ (tools/sarmap/shipped_data.cpp finds it
# there from the binary's own path).
get_property(SARMAP_MODULES GLOBAL PROPERTY SARMAP_MODULES)
install(TARGETS sarmap ${SARMAP_MODULES} sarmap_xsimd EXPORT sarmapTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(DIRECTORY engine kernels DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/sarmap
  FILES_MATCHING PATTERN "*.hpp")
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/generated/engine/core/version.hpp
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/sarmap/engine/core)
# The shipped model and the arenas (with the meshes they may name), laid out as
# in datasets/; not the fixtures or any training data.
set(SARMAP_INSTALL_DATADIR ${CMAKE_INSTALL_DATADIR}/sarmap)
install(DIRECTORY datasets/arenas DESTINATION ${SARMAP_INSTALL_DATADIR})
install(FILES datasets/models/ramps-dgcnn.safetensors DESTINATION ${SARMAP_INSTALL_DATADIR}/models)
install(EXPORT sarmapTargets NAMESPACE sarmap::
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/sarmap)
configure_package_config_file(cmake/sarmapConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/sarmapConfig.cmake
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/sarmap
  PATH_VARS SARMAP_INSTALL_DATADIR)
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/sarmapConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/sarmapConfig.cmake
  ${CMAKE_CURRENT_BINARY_DIR}/sarmapConfigVersion.cmake
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/sarmap)
