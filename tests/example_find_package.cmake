# Installs the built sarmap into a scratch prefix, then configures, builds and
# runs examples/find_package against it on the tiny committed sequence, as an
# out-of-tree front end would.
file(REMOVE_RECURSE ${WORK_DIR})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${SARMAP_BUILD_DIR} --prefix ${WORK_DIR}/prefix
  RESULT_VARIABLE rc OUTPUT_QUIET)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "installing sarmap failed (${rc})")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -S ${EXAMPLE_SOURCE_DIR} -B ${WORK_DIR}/build
  -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix
  "-DCMAKE_CXX_FLAGS=${EXAMPLE_CXX_FLAGS}" "-DCMAKE_EXE_LINKER_FLAGS=${EXAMPLE_LINKER_FLAGS}"
  RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "configuring the example failed (${rc})")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK_DIR}/build RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "building the example failed (${rc})")
endif()
execute_process(COMMAND ${WORK_DIR}/build/sarmap_example ${EXAMPLE_SEQUENCE} ${WORK_DIR}/run
  RESULT_VARIABLE rc OUTPUT_VARIABLE out)
message(STATUS "${out}")
if(NOT rc EQUAL 0 OR NOT out MATCHES "sarmap [0-9]+\\.[0-9]+\\.[0-9]+: 2 scans")
  message(FATAL_ERROR "the example did not run as expected (${rc}): ${out}")
endif()
# The library's write_run wrote the run's whole folder, manifest last.
foreach(name manifest.json map.sarmap segments.json graph.json profile.json)
  if(NOT EXISTS ${WORK_DIR}/run/${name})
    message(FATAL_ERROR "the example's run folder has no ${name}")
  endif()
endforeach()
