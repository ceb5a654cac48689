# sarmap_add_module(NAME SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# Each engine module is its own static library (sarmap_NAME), so the arrows of
# docs/architecture.md are enforced by the link graph and a module's tests build
# only what it depends on. sarmap::sarmap links them all.
function(sarmap_add_module name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  set(target sarmap_${name})
  add_library(${target} STATIC ${ARG_SOURCES})
  add_library(sarmap::${name} ALIAS ${target})
  target_compile_options(${target} PRIVATE ${SARMAP_BASELINE_ARCH_FLAGS} ${SARMAP_WARNING_FLAGS})
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>
    $<BUILD_INTERFACE:${PROJECT_BINARY_DIR}/generated>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/sarmap>)
  target_link_libraries(${target} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  set_property(GLOBAL APPEND PROPERTY SARMAP_MODULES ${target})
  target_link_libraries(sarmap INTERFACE ${target})
endfunction()
