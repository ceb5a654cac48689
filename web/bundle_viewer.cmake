# Runs esbuild on web/viewer/main.js into BUNDLE (web/CMakeLists.txt), or
# explains, without failing the build, why the viewer is not built.
set(esbuild ${WEB_DIR}/node_modules/.bin/esbuild)
if(NOT EXISTS ${esbuild} OR NOT EXISTS ${WEB_DIR}/node_modules/three/package.json)
  file(REMOVE ${BUNDLE})
  message(STATUS "sarmap viewer not bundled: ${WEB_DIR}/node_modules is missing "
    "(tools/install-deps.sh runs npm ci there); `sarmap view` needs it")
  return()
endif()
get_filename_component(bundle_dir ${BUNDLE} DIRECTORY)
file(MAKE_DIRECTORY ${bundle_dir})
execute_process(
  COMMAND ${esbuild} ${WEB_DIR}/viewer/main.js --bundle --format=iife --minify
    --target=es2020 --log-level=warning --outfile=${BUNDLE}
  WORKING_DIRECTORY ${WEB_DIR}
  RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  file(REMOVE ${BUNDLE})
  message(FATAL_ERROR "esbuild could not bundle ${WEB_DIR}/viewer/main.js (${rc})")
endif()
