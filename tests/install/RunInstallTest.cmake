# Installs the mixcon build into PREFIX, runs the installed `mixcon` program (--version, and one
# shipped example when EXAMPLE is set) with no LD_LIBRARY_PATH, so that it must find libmixcon
# and its dependencies through its install RPATH, then configures, builds and runs the
# downstream project.
file(REMOVE_RECURSE ${PREFIX} ${WORK}/build ${WORK}/example)
execute_process(COMMAND ${CMAKE_COMMAND} --install ${MIXCON_BUILD_DIR} --prefix ${PREFIX}
                RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "install failed: ${rc}")
endif()

if(APP)
  set(app ${PREFIX}/bin/mixcon)
  if(NOT EXISTS ${app})
    message(FATAL_ERROR "the installed program ${app} is missing")
  endif()
  execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=LD_LIBRARY_PATH ${app} --version
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(rc)
    message(FATAL_ERROR "installed `mixcon --version` failed (${rc}): ${out}${err}")
  endif()
  if(NOT out MATCHES "mixcon ${VERSION}")
    message(FATAL_ERROR "installed `mixcon --version` printed '${out}', not 'mixcon ${VERSION}'")
  endif()
  if(EXAMPLE)
    execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=LD_LIBRARY_PATH
                            ${app} run ${EXAMPLE} --output ${WORK}/example
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(rc)
      message(FATAL_ERROR "installed `mixcon run ${EXAMPLE}` failed (${rc}):\n${out}${err}")
    endif()
    if(NOT EXISTS ${WORK}/example/summary.json)
      message(FATAL_ERROR "installed `mixcon run ${EXAMPLE}` wrote no summary.json:\n${out}")
    endif()
  endif()
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
