# Shared by the install ctests (install_package.cmake, installed_plots.cmake): a fresh
# WORK_DIR holding the install prefix, and run(COMMAND...), which fails the test on a non-zero
# exit and leaves the command's standard output in last_output, its error output in last_error.
file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  set(last_output "${out}" PARENT_SCOPE)
  set(last_error "${err}" PARENT_SCOPE)
endfunction()
