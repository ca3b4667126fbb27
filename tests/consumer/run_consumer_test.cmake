# cmake -DBUILD_DIR=<eulervop build> -DSOURCE_DIR=<tests/consumer> -DWORK_DIR=<scratch> -DSCENE=<toml>
#       [-DCONFIG=<Release>] -P run_consumer_test.cmake
# Installs the build into WORK_DIR/prefix, configures and builds the consumer against it with
# CMAKE_PREFIX_PATH, and runs it (and the scene consumer if the package has eulervop::scene).
include(${CMAKE_CURRENT_LIST_DIR}/../cmake_script_support.cmake)
require_script_variables(run_consumer_test.cmake BUILD_DIR SOURCE_DIR WORK_DIR SCENE)

file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
run_step("install" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix} --config ${CONFIG})
run_step("configure the consumer" ${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${WORK_DIR}/build
         -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_BUILD_TYPE=${CONFIG})
run_step("build the consumer" ${CMAKE_COMMAND} --build ${WORK_DIR}/build --config ${CONFIG})
run_step("run the consumer" ${WORK_DIR}/build/consumer)
if(EXISTS ${WORK_DIR}/build/consumer_scene)
  run_step("run the scene consumer" ${WORK_DIR}/build/consumer_scene ${SCENE})
endif()
file(REMOVE_RECURSE ${WORK_DIR})
