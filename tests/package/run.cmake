# Runs the consumer project: cmake -DMODE=find_package|fetchcontent -DSOURCE=... -DWORK=... -P run.cmake
file(REMOVE_RECURSE ${WORK})
set(generator_args -DCMAKE_BUILD_TYPE=Release)
function(run_step)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}")
  endif()
endfunction()
if(MODE STREQUAL "find_package")
  run_step(${CMAKE_COMMAND} -S ${SOURCE} -B ${WORK}/lib -DRADIOSITY_BUILD_TESTS=OFF
           -DRADIOSITY_BUILD_EXAMPLES=OFF -DRADIOSITY_BUILD_BENCHMARKS=OFF ${generator_args})
  run_step(${CMAKE_COMMAND} --install ${WORK}/lib --prefix ${WORK}/prefix)
  run_step(${CMAKE_COMMAND} -S ${SOURCE}/tests/package -B ${WORK}/consumer
           -DCMAKE_PREFIX_PATH=${WORK}/prefix -DRADIOSITY_CONSUMER_MODE=find_package ${generator_args})
else()
  run_step(${CMAKE_COMMAND} -S ${SOURCE}/tests/package -B ${WORK}/consumer
           -DRADIOSITY_SOURCE_DIR=${SOURCE} -DRADIOSITY_CONSUMER_MODE=fetchcontent ${generator_args})
endif()
run_step(${CMAKE_COMMAND} --build ${WORK}/consumer)
run_step(${WORK}/consumer/consumer)
