# Installs the built sarmap into a scratch prefix and runs the installed binary
# as a user without the source tree would: `demo` on the shipped default arena
# and `run` with the shipped model, both found in PREFIX/share/sarmap/. The
# installed binary never looks in the source tree (only the build-tree binary
# does), and the second half checks that: with share/sarmap/ moved away its
# errors name the prefix and not the source tree's datasets/, and
# SARMAP_DATA_DIR points it at the moved folder. Also checks that the install
# holds the package and no test, benchmark or fixture files, and that the
# installed binary finds the viewer's script in the prefix. With PYTHON (the
# build has the Python module), the installed package imports from the
# prefix, maps a sequence and finds the shipped model there, and only there.
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
file(REAL_PATH ${WORK_DIR} WORK_DIR)  # /proc/self/exe gives the binary's real path
set(prefix ${WORK_DIR}/prefix)
set(data ${prefix}/share/sarmap)
execute_process(COMMAND ${CMAKE_COMMAND} --install ${SARMAP_BUILD_DIR} --prefix ${prefix}
  RESULT_VARIABLE rc OUTPUT_QUIET)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "installing sarmap failed (${rc})")
endif()

# What the prefix holds: the binary, the static libraries, the CMake package,
# the headers, the model and the arenas (and the viewer's script when the
# build bundled it); nothing else.
foreach(f bin/sarmap lib/libsarmap_core.a lib/cmake/sarmap/sarmapConfig.cmake
    include/sarmap/engine/core/version.hpp include/sarmap/engine/pipeline/mapper.hpp
    share/sarmap/models/ramps-dgcnn.safetensors share/sarmap/arenas/esogu-6x4.json
    share/sarmap/arenas/building-52x15.json)
  if(NOT EXISTS ${prefix}/${f})
    message(FATAL_ERROR "the install lacks ${f}")
  endif()
endforeach()
if(PYTHON)
  set(python_package ${PYTHON_INSTALL_DIR}/sarmap)
  foreach(f __init__.py _data.py _data_paths.py _scan.py)
    if(NOT EXISTS ${prefix}/${python_package}/${f})
      message(FATAL_ERROR "the install lacks ${python_package}/${f}")
    endif()
  endforeach()
  set(python_files "|${python_package}/(_?[a-z_]+\\.py|_sarmap\\.cpython-[a-z0-9_-]+\\.so)")
endif()
file(GLOB_RECURSE installed RELATIVE ${prefix} ${prefix}/*)
foreach(f ${installed})
  if(NOT f MATCHES "^(bin/sarmap|lib/libsarmap_[a-z_]+\\.a|lib/cmake/sarmap/[A-Za-z-]+\\.cmake|include/sarmap/(engine|kernels)/.*\\.hpp|share/sarmap/(models/ramps-dgcnn\\.safetensors|arenas/[a-z0-9-]+\\.json|arenas/meshes/.*|viewer\\.js)${python_files})$")
    message(FATAL_ERROR "the install holds ${f}, which is no part of the package")
  endif()
endforeach()

# Runs PREFIX/bin/sarmap ARGS... from the scratch folder, with SARMAP_DATA_DIR
# unset unless ENV_DATA_DIR is given.
# `cmake -E env` arguments: SARMAP_DATA_DIR set to DIR, or unset when DIR is empty.
function(data_dir_env dir var)
  if(dir)
    set(${var} SARMAP_DATA_DIR=${dir} PARENT_SCOPE)
  else()
    set(${var} --unset=SARMAP_DATA_DIR PARENT_SCOPE)
  endif()
endfunction()

function(run_installed)
  cmake_parse_arguments(ARG "" "ENV_DATA_DIR" "" ${ARGN})
  data_dir_env("${ARG_ENV_DATA_DIR}" env)
  execute_process(COMMAND ${CMAKE_COMMAND} -E env ${env} ${prefix}/bin/sarmap ${ARG_UNPARSED_ARGUMENTS}
    WORKING_DIRECTORY ${WORK_DIR} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  set(rc ${rc} PARENT_SCOPE)
  set(out "${out}" PARENT_SCOPE)
  set(err "${err}" PARENT_SCOPE)
endfunction()

function(expect_success what)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}\n${err}")
  endif()
endfunction()

# The model a run's manifest names.
function(model_of run_dir var)
  file(READ ${run_dir}/manifest.json manifest)
  string(JSON model GET "${manifest}" config classifier model)
  set(${var} ${model} PARENT_SCOPE)
endfunction()

# The demo on the shipped default arena (the labels classifier, to stay fast).
run_installed(demo --out ${WORK_DIR}/demo --classifier labels)
expect_success("sarmap demo from the prefix")
string(FIND "${out}" "arena esogu-6x4 (${data}/arenas/esogu-6x4.json)" at)
if(at EQUAL -1)
  message(FATAL_ERROR "the demo did not use the installed default arena:\n${out}")
endif()
message(STATUS "${out}")

# The viewer's script, when the build bundled it (web/node_modules was
# installed): `view` finds it in the prefix and writes the demo's page.
if(EXISTS ${SARMAP_BUILD_DIR}/share/sarmap/viewer.js)
  if(NOT EXISTS ${data}/viewer.js)
    message(FATAL_ERROR "the install lacks share/sarmap/viewer.js, which the build bundled")
  endif()
  run_installed(view ${WORK_DIR}/demo/run --quiet)
  expect_success("sarmap view from the prefix")
  if(NOT EXISTS ${WORK_DIR}/demo/run/view.html)
    message(FATAL_ERROR "sarmap view from the prefix wrote no view.html")
  endif()
endif()

# A short run with the shipped model.
run_installed(simulate ${data}/arenas/esogu-6x4.json --out ${WORK_DIR}/sequence --frames 3 --quiet)
expect_success("sarmap simulate from the prefix")
run_installed(run ${WORK_DIR}/sequence --out ${WORK_DIR}/run --quiet)
expect_success("sarmap run from the prefix")
model_of(${WORK_DIR}/run model)
if(NOT model STREQUAL "${data}/models/ramps-dgcnn.safetensors")
  message(FATAL_ERROR "the run used the model ${model}, not the installed one")
endif()

# The Python package from the prefix, in a fresh interpreter whose working
# folder is not the source tree: it maps the sequence above and names the
# shipped model it finds (SARMAP_DATA_DIR unset unless ENV_DATA_DIR is given).
function(run_installed_python script)
  cmake_parse_arguments(ARG "" "ENV_DATA_DIR" "" ${ARGN})
  data_dir_env("${ARG_ENV_DATA_DIR}" env)
  execute_process(COMMAND ${CMAKE_COMMAND} -E env ${env} PYTHONPATH=${prefix}/${PYTHON_INSTALL_DIR}
      PYTHONDONTWRITEBYTECODE=1 ${PYTHON} -c "${script}"
    WORKING_DIRECTORY ${WORK_DIR} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  set(rc ${rc} PARENT_SCOPE)
  set(out "${out}" PARENT_SCOPE)
  set(err "${err}" PARENT_SCOPE)
endfunction()
set(python_maps [=[
import sarmap
print(sarmap.__file__)
print(sarmap.shipped_model())
sequence = sarmap.open_sequence('sequence')
mapper = sarmap.Mapper({'classifier': {'kind': 'labels'}}, sensor=sequence.sensor)
for points, pose, origin in sequence:
    mapper.integrate(points, pose, frame='world', origin=origin)
mapper.write('python-run', input=sequence)
print(mapper.scans, len(mapper.occupied_voxels()[0]))
]=])
if(PYTHON)
  run_installed_python("${python_maps}")
  expect_success("import sarmap from the prefix")
  if(NOT out MATCHES "^${prefix}/${python_package}/__init__.py\n${data}/models/ramps-dgcnn.safetensors\n3 [1-9][0-9]*\n$")
    message(FATAL_ERROR "the installed package did not map from the prefix with its own data:\n${out}")
  endif()
  if(NOT EXISTS ${WORK_DIR}/python-run/manifest.json)
    message(FATAL_ERROR "the installed package wrote no run")
  endif()
endif()

# share/sarmap/ gone: each error names the place looked, never the source tree.
file(RENAME ${data} ${prefix}/share/sarmap-moved)
function(expect_missing command file)
  string(FIND "${err}" "${data}/${file}, beside the binary ${prefix}/bin/sarmap" named_prefix)
  string(FIND "${err}" "${SOURCE_DIR}/datasets" named_source)
  if(NOT rc EQUAL 1 OR named_prefix EQUAL -1 OR NOT named_source EQUAL -1)
    message(FATAL_ERROR "sarmap ${command} without share/sarmap/ (${rc}): ${err}")
  endif()
endfunction()
run_installed(run ${WORK_DIR}/sequence --out ${WORK_DIR}/run-nodata --quiet)
expect_missing(run models/ramps-dgcnn.safetensors)
run_installed(demo --out ${WORK_DIR}/demo-nodata --classifier labels)
expect_missing(demo arenas/esogu-6x4.json)
if(PYTHON)
  run_installed_python("import sarmap; sarmap.shipped_model()")
  string(FIND "${err}" "${data}/models/ramps-dgcnn.safetensors, beside the installed package" named_prefix)
  string(FIND "${err}" "${SOURCE_DIR}/datasets" named_source)
  if(rc EQUAL 0 OR named_prefix EQUAL -1 OR NOT named_source EQUAL -1 OR NOT err MATCHES "FileNotFoundError")
    message(FATAL_ERROR "the installed package without share/sarmap/ (${rc}): ${err}")
  endif()
  run_installed_python("import sarmap; print(sarmap.shipped_model())" ENV_DATA_DIR ${prefix}/share/sarmap-moved)
  expect_success("the installed package with SARMAP_DATA_DIR")
  if(NOT out STREQUAL "${prefix}/share/sarmap-moved/models/ramps-dgcnn.safetensors\n")
    message(FATAL_ERROR "with SARMAP_DATA_DIR the installed package found the model ${out}")
  endif()
endif()
run_installed(run ${WORK_DIR}/sequence --out ${WORK_DIR}/run-env --quiet ENV_DATA_DIR ${prefix}/share/sarmap-moved)
expect_success("sarmap run with SARMAP_DATA_DIR")
model_of(${WORK_DIR}/run-env model)
if(NOT model STREQUAL "${prefix}/share/sarmap-moved/models/ramps-dgcnn.safetensors")
  message(FATAL_ERROR "with SARMAP_DATA_DIR the run used the model ${model}")
endif()
file(REMOVE_RECURSE ${WORK_DIR})
