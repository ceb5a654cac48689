# Every dependency comes from Debian 12's packages (tools/install-deps.sh).
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(TBB REQUIRED)
find_package(embree 3 REQUIRED)
find_package(xsimd 8 REQUIRED)
# Debian's xsimd 8.1 exports a link to "xtl" although xsimd is header-only and
# does not need it (and libxtl-dev is not a dependency): take its headers only.
get_target_property(SARMAP_XSIMD_INCLUDE_DIRS xsimd INTERFACE_INCLUDE_DIRECTORIES)
add_library(sarmap_xsimd INTERFACE)
target_include_directories(sarmap_xsimd SYSTEM INTERFACE ${SARMAP_XSIMD_INCLUDE_DIRS})
find_package(nlohmann_json 3 REQUIRED)
find_package(PNG REQUIRED)
find_package(assimp REQUIRED)
if(SARMAP_BUILD_TOOLS)
  find_package(CLI11 REQUIRED)
endif()
# ROS 1 bags in (engine/io_rosbag) through Debian's librosbag-storage-dev
# (the bag API of librosbag-dev, without its player and recorder), ON when it
# is found. Its CMake package (rosbag_storageConfig) loads ament's CMake
# helpers, which run a Python that must have ament's modules, so the headers
# and the four libraries sarmap calls are found directly instead.
option(SARMAP_WITH_ROSBAG "Read ROS 1 bags when librosbag-storage-dev is installed" ON)
set(SARMAP_HAVE_ROSBAG OFF)
if(SARMAP_WITH_ROSBAG)
  find_path(SARMAP_ROSBAG_INCLUDE_DIR rosbag/bag.h)
  # rosbag/bag.h includes ROS 2's pluginlib, which Debian keeps in folders of its own.
  set(SARMAP_ROSBAG_INCLUDE_DIRS ${SARMAP_ROSBAG_INCLUDE_DIR})
  foreach(header pluginlib/class_loader.hpp class_loader/class_loader.hpp rcpputils/shared_library.hpp
                 rcutils/types.h ament_index_cpp/get_package_prefix.hpp)
    string(REGEX REPLACE "/.*" "" package ${header})
    find_path(SARMAP_ROSBAG_${package}_DIR ${header} PATH_SUFFIXES ${package})
    list(APPEND SARMAP_ROSBAG_INCLUDE_DIRS ${SARMAP_ROSBAG_${package}_DIR})
  endforeach()
  set(SARMAP_ROSBAG_LIBRARIES)
  foreach(lib rosbag_storage roscpp_serialization rostime cpp_common)
    find_library(SARMAP_ROSBAG_${lib}_LIBRARY ${lib})
    list(APPEND SARMAP_ROSBAG_LIBRARIES ${SARMAP_ROSBAG_${lib}_LIBRARY})
  endforeach()
  if(NOT "${SARMAP_ROSBAG_INCLUDE_DIRS};${SARMAP_ROSBAG_LIBRARIES}" MATCHES "NOTFOUND")
    set(SARMAP_HAVE_ROSBAG ON)
  else()
    message(STATUS "librosbag-storage-dev not found: sarmap is built without ROS 1 bag input")
  endif()
endif()
if(SARMAP_BUILD_TESTS)
  find_package(GTest REQUIRED)
  # OctoMap is a peer the tests and benchmarks compare against, never a
  # dependency of the library.
  find_package(octomap REQUIRED)
endif()
if(SARMAP_BUILD_BENCH)
  find_package(benchmark REQUIRED)
  find_package(octomap REQUIRED)
endif()
