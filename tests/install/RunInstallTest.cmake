# Installs the mixcon build into PREFIX, then configures, builds and runs the downstream project.
file(REMOVE_RECURSE ${PREFIX} ${WORK}/build)
execute_process(COMMAND ${CMAKE_COMMAND} --install ${MIXCON_BUILD_DIR} --prefix ${PREFIX}
                RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "install failed: ${rc}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE} -B ${WORK}/build
                        -DCMAKE_PREFIX_PATH=${PREFIX} -DKokkos_DIR=${Kokkos_ROOT}
                        -DCMAKE_BUILD_TYPE=${CONFIG}
                RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "downstream configure failed: ${rc}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK}/build RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "downstream build failed: ${rc}")
endif()
execute_process(COMMAND ${WORK}/build/downstream RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "downstream program failed: ${rc}")
endif()
