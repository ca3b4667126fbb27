# cmake -DSOURCE_DIR=<eulervop checkout> -DWORK_DIR=<scratch> [-DCONFIG=Release] [-DBUILD_DIR=<build>]
#       -P run_installed_program_test.cmake
# With BUILD_DIR, installs that existing build instead of making (and deleting) a fresh one: the
# quick form for the default suite. The program looks for its scripts only next to itself, so an
# installed copy cannot reach the build tree's scripts either way.
# The installed program must not need the tree it was built from: configures and builds the
# `eulervop` target in WORK_DIR/build, installs it to WORK_DIR/prefix, deletes the build tree,
# then runs the installed bin/eulervop from another directory: `reference --certify` with the
# installed certificate module, and `report`, which must draw fig1.png with the plot script
# installed in share/eulervop. Where matplotlib is missing (the
# script was found and ran, but cannot draw) it prints "SKIPPED: ...", which CTest reports as a
# skip (SKIP_REGULAR_EXPRESSION); any other outcome without fig1.png is a failure.
include(${CMAKE_CURRENT_LIST_DIR}/../cmake_script_support.cmake)
require_script_variables(run_installed_program_test.cmake SOURCE_DIR WORK_DIR)

file(REMOVE_RECURSE ${WORK_DIR})
set(build ${WORK_DIR}/build)
set(prefix ${WORK_DIR}/prefix)
set(run_dir ${WORK_DIR}/run)
if(BUILD_DIR)
  run_step("install" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix} --config ${CONFIG})
else()
  run_step("configure" ${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${build} -DCMAKE_BUILD_TYPE=${CONFIG}
           -DEULERVOP_BUILD_TESTS=OFF -DEULERVOP_BUILD_BENCHMARKS=OFF)
  run_step("build" ${CMAKE_COMMAND} --build ${build} --config ${CONFIG} --target eulervop --parallel 2)
  run_step("install" ${CMAKE_COMMAND} --install ${build} --prefix ${prefix} --config ${CONFIG})
  file(REMOVE_RECURSE ${build})
  if(EXISTS ${build})
    message(FATAL_ERROR "could not delete the build tree ${build}")
  endif()
endif()
foreach(script plot_fig1.py plot_work_precision.py plot_regime_map.py plot_common.py)
  if(NOT EXISTS ${prefix}/share/eulervop/${script})
    message(FATAL_ERROR "not installed: share/eulervop/${script}")
  endif()
endforeach()

file(MAKE_DIRECTORY ${run_dir})
# --certify loads the certificate module installed beside the program (lib*/eulervop).
execute_process(COMMAND ${prefix}/bin/eulervop reference --certify --tau-end 1 --samples 3 --out certified.csv
                WORKING_DIRECTORY ${run_dir} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
file(READ ${run_dir}/certified.csv certified)
if(NOT rc EQUAL 0 OR NOT certified MATCHES "# certified_max_error: ")
  message(FATAL_ERROR "installed eulervop reference --certify failed (${rc}):\n${out}\n${err}")
endif()
execute_process(COMMAND ${prefix}/bin/eulervop report --tau-end 20 --out-dir out
                WORKING_DIRECTORY ${run_dir} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "installed eulervop report failed (${rc}):\n${out}\n${err}")
endif()
if(EXISTS ${run_dir}/out/fig1.png)
  message("fig1.png written by the installed program")
elseif(err MATCHES "^figure skipped: matplotlib not found")
  message("SKIPPED: matplotlib is missing, so the installed plot script could not draw\n${err}")
else()
  message(FATAL_ERROR "no fig1.png from the installed program:\n${err}")
endif()
file(REMOVE_RECURSE ${WORK_DIR})
