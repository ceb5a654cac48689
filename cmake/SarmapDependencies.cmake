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
